// Tests of synthetic room captures (synth/room.h, synth/body.h, the hand-held rig, mattes): the
// written matte is the subject's coverage as the renderer computes it for the subject alone, the
// room fills the background, the images carry no alpha and the loader sees an opaque dataset with
// eval_matte_path on every frame, the two layouts differ, and the team's scan renders in a room.
#include "synth/room.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "host/dataset/dataset.h"
#include "mesh/embree_scene.h"
#include "synth/body.h"
#include "synth/matte.h"
#include "synth/synthesize.h"

namespace lorgnette::synth {
namespace {

namespace fs = std::filesystem;

const Subject& head_with_body() {
  static const Subject s = procedural_subject(random_head_params(0), HeadMeshOptions{256, 128, 512}, true);
  return s;
}

SynthOptions room_options(int room) {
  SynthOptions o;
  o.room = room;
  o.views = 4;
  o.width = 72, o.height = 96;
  o.samples_per_axis = 3;
  o.seed = 3;
  o.yaw_min_deg = -40.0f, o.yaw_max_deg = 40.0f;
  o.pitch_min_deg = -8.0f, o.pitch_max_deg = 8.0f;
  return o;
}

Camera first_camera(const Subject& s, const SynthOptions& o) {
  return make_camera_rig(rig_for(s, o))[1].camera;
}

RenderedView render_in_room(const Subject& s, int room, const Camera& cam) {
  RoomScene rs = subject_in_room(s, room);
  RenderSettings settings{3, room_sky(), 1};
  settings.subject_triangles = rs.subject_triangles;
  mesh::EmbreeScene scene(std::move(rs.mesh));
  return render_view(scene, cam, StudioLighting{}, settings);
}

// The matte is exactly the coverage of the subject rendered alone (same sub-pixel rays): at most
// 0.1 % of pixels may differ by one sample of nine (Embree edge ties between two BVHs).
TEST(Room, MatteEqualsTheSubjectsOwnCoverage) {
  const Subject& s = head_with_body();
  SynthOptions o = room_options(1);
  Camera cam = first_camera(s, o);
  RenderedView v = render_in_room(s, 1, cam);
  mesh::EmbreeScene alone(s.mesh, s.mesh_to_dataset);
  RenderedView a = render_view(alone, cam, StudioLighting{}, RenderSettings{3, std::nullopt, 1});
  int differ = 0, covered = 0;
  for (int y = 0; y < int(cam.height); ++y)
    for (int x = 0; x < int(cam.width); ++x) {
      float d = std::abs(v.matte.at(x, y, 0) - a.rgba.at(x, y, 3));
      EXPECT_LE(d, 1.0f / 9.0f + 1e-6f) << x << "," << y;
      differ += d > 1e-6f;
      covered += a.rgba.at(x, y, 3) > 0.5f;
      EXPECT_EQ(v.rgba.at(x, y, 3), 1.0f);  // opaque everywhere
    }
  EXPECT_LE(differ, int(0.001 * cam.width * cam.height) + 1);
  EXPECT_GT(covered, int(0.15 * cam.width * cam.height))
      << "the subject should fill a good part of a phone view";
}

// Behind the subject the room is seen: at least 85 % of the non-subject pixels are not the sky
// colour, and they are textured (standard deviation of luminance above 0.03), in the textured layouts.
TEST(Room, RoomIsSeenBehindTheSubject) {
  const Subject& s = head_with_body();
  for (int room = 1; room <= kRoomLayouts; ++room) {
    if (room == kPlainRoomLayout) continue;  // plain by design (next test)
    RenderedView v = render_in_room(s, room, first_camera(s, room_options(room)));
    int bg = 0, room_px = 0;
    double sum = 0, sum2 = 0;
    for (int y = 0; y < v.rgba.height; ++y)
      for (int x = 0; x < v.rgba.width; ++x) {
        if (v.matte.at(x, y, 0) > 0.0f) continue;
        ++bg;
        Eigen::Vector3f c(v.rgba.at(x, y, 0), v.rgba.at(x, y, 1), v.rgba.at(x, y, 2));
        if ((c - room_sky()).cwiseAbs().maxCoeff() > 1e-3f) ++room_px;
        double l = c.mean();
        sum += l, sum2 += l * l;
      }
    ASSERT_GT(bg, 0);
    EXPECT_GT(room_px, int(0.85 * bg)) << "room " << room;
    double mean = sum / bg;
    EXPECT_GT(std::sqrt(std::max(0.0, sum2 / bg - mean * mean)), 0.03)
        << "room " << room << " looks untextured";
  }
}

// Same camera, two layouts: the backgrounds differ (mean absolute difference above 0.05 linear),
// the subject does not (its matte is identical).
TEST(Room, TwoLayoutsDiffer) {
  const Subject& s = head_with_body();
  Camera cam = first_camera(s, room_options(1));
  RenderedView a = render_in_room(s, 1, cam), b = render_in_room(s, 2, cam);
  double diff = 0;
  int n = 0;
  for (int y = 0; y < a.rgba.height; ++y)
    for (int x = 0; x < a.rgba.width; ++x) {
      EXPECT_EQ(a.matte.at(x, y, 0), b.matte.at(x, y, 0));
      if (a.matte.at(x, y, 0) > 0.0f) continue;
      for (int c = 0; c < 3; ++c) diff += std::abs(a.rgba.at(x, y, c) - b.rgba.at(x, y, c));
      n += 3;
    }
  EXPECT_GT(diff / n, 0.05);
}

// The written dataset: RGB images without alpha, a matte per frame referenced as eval_matte_path and
// never as mask_path (round trip through the 8-bit file within half a step), the loader sees no alpha.
TEST(Room, DatasetHasNoAlphaAndAMattePerFrame) {
  fs::path dir = fs::path(LORGNETTE_TEST_TMP) / "synth" / "room_dataset";
  fs::remove_all(dir);
  fs::create_directories(dir.parent_path());
  SynthOptions o = room_options(2);
  o.force = true;
  synthesize_dataset(head_with_body(), dir.string(), o);
  nlohmann::json tj = nlohmann::json::parse(std::ifstream(dir / "transforms.json"));
  ASSERT_EQ(tj.at("frames").size(), 4u);
  for (const auto& f : tj.at("frames")) {
    Image img = read_image((dir / f.at("file_path").get<std::string>()).string());
    EXPECT_EQ(img.channels, 3);
    Image m = read_matte((dir / f.at("eval_matte_path").get<std::string>()).string());
    EXPECT_EQ(m.width, img.width);
    // The true mattes are for evaluation only: as a mask_path the loader would cut the subject out
    // for training, and the room model would have nothing to learn.
    EXPECT_FALSE(f.contains("mask_path")) << f.dump();
    double cover = 0;
    for (float v : m.pixels) cover += v;
    EXPECT_GT(cover, 0.1 * m.pixels.size());
  }
  // The evaluation files as eval and the benchmarks read them: every frame, by image stem.
  const auto files = eval_files_by_stem(dir.string());
  ASSERT_EQ(files.size(), tj["frames"].size());
  for (const auto& f : tj["frames"]) {
    const EvalFiles& e = files.at(fs::path(f["file_path"].get<std::string>()).stem().string());
    EXPECT_EQ(e.matte, f["eval_matte_path"].get<std::string>());
    EXPECT_EQ(e.depth, f.value("depth_path", ""));
  }
  EXPECT_TRUE(eval_files_by_stem((dir / "no-such-folder").string()).empty());
  dataset::Dataset ds = dataset::load_dataset(dir.string(), {});
  EXPECT_FALSE(ds.has_alpha);
  nlohmann::json gt = nlohmann::json::parse(std::ifstream(dir / "ground_truth.json"));
  EXPECT_EQ(gt.at("room").at("layout"), 2);
  // Hand-held: the views sweep the yaw range in order.
  for (size_t i = 1; i < gt.at("views").size(); ++i)
    EXPECT_GT(gt["views"][i]["yaw_deg"].get<float>(), gt["views"][i - 1]["yaw_deg"].get<float>());
}

TEST(Room, MatteFileRoundTrips) {
  Image m(5, 1, 1);
  for (int i = 0; i < 5; ++i) m.pixels[i] = i / 4.0f;
  fs::path p = fs::path(LORGNETTE_TEST_TMP) / "synth" / "matte.png";
  fs::create_directories(p.parent_path());
  write_matte(p.string(), m);
  Image r = read_matte(p.string());
  for (int i = 0; i < 5; ++i)
    EXPECT_NEAR(r.pixels[i], m.pixels[i], 0.5f / 255.0f + 1e-5f);  // half a step + float rounding
}

// The plain room: its paint is one colour (every texel the wall's albedo) and the lit wall is seen
// behind the subject; the skin's highlight brightens the subject only (its matte unchanged, the room
// identical); a wall closer than 200 mm is refused.
TEST(Room, PlainWallIsUntexturedAndTheHighlightLiesOnTheSubject) {
  const Subject& s = head_with_body();
  const Camera cam = first_camera(s, room_options(kPlainRoomLayout));
  auto render = [&](float wall_mm, float specular) {
    RoomPlacement plain;
    plain.wall_mm = wall_mm;
    RoomScene rs = subject_in_room(s, kPlainRoomLayout, plain);
    RenderSettings settings{3, room_sky(), 1};
    settings.subject_triangles = rs.subject_triangles;
    mesh::EmbreeScene scene(std::move(rs.mesh));
    StudioLighting light;
    light.specular = specular;
    return render_view(scene, cam, light, settings);
  };
  const RenderedView near = render(600.0f, 0.0f), shiny = render(600.0f, 0.6f);
  RoomPlacement paint;
  paint.layout = kPlainRoomLayout;
  const mesh::TriMesh room = make_room(paint);
  ASSERT_FALSE(room.textures.empty());
  for (const Image& t : room.textures)
    for (size_t i = 0; i < t.pixels.size(); ++i) ASSERT_EQ(t.pixels[i], paint.wall_rgb[int(i % 3)]);
  int wall = 0;
  double sum = 0, subject_gain = 0;
  for (int y = 0; y < near.rgba.height; ++y)
    for (int x = 0; x < near.rgba.width; ++x) {
      EXPECT_EQ(near.matte.at(x, y, 0), shiny.matte.at(x, y, 0));
      const double l = (near.rgba.at(x, y, 0) + near.rgba.at(x, y, 1) + near.rgba.at(x, y, 2)) / 3.0;
      const double ls = (shiny.rgba.at(x, y, 0) + shiny.rgba.at(x, y, 1) + shiny.rgba.at(x, y, 2)) / 3.0;
      if (near.matte.at(x, y, 0) > 0.0f) {
        EXPECT_GE(ls, l - 1e-6);
        subject_gain = std::max(subject_gain, ls - l);
        continue;
      }
      EXPECT_EQ(ls, l);  // no highlight on the room
      if (!std::isfinite(near.depth.at(x, y, 0))) ++wall, sum += l;
    }
  ASSERT_GT(wall, 100);
  EXPECT_GT(sum / wall, 0.3);  // the off-white wall, lit
  EXPECT_GT(subject_gain, 0.1);
  RoomPlacement bad;
  bad.layout = kPlainRoomLayout;
  bad.wall_mm = 50.0f;
  EXPECT_THROW(make_room(bad), std::runtime_error);
}

// The plain room at `wall_mm` behind, with or without its window, lit as synth lights it.
RenderedView render_plain(const Subject& s, const Camera& cam, float wall_mm, bool window,
                          const Eigen::Vector3f& wall_rgb) {
  RoomPlacement plain;
  plain.wall_mm = wall_mm, plain.window = window, plain.wall_rgb = wall_rgb;
  RoomScene rs = subject_in_room(s, kPlainRoomLayout, plain);
  RenderSettings settings{3, room_sky(), 1};
  settings.subject_triangles = rs.subject_triangles;
  mesh::EmbreeScene scene(std::move(rs.mesh));
  return render_view(scene, cam, room_lighting(plain, StudioLighting{}), settings);
}

Eigen::Vector3f rgb_at(const RenderedView& v, int x, int y) {
  return {v.rgba.at(x, y, 0), v.rgba.at(x, y, 1), v.rgba.at(x, y, 2)};
}

float luminance(const Eigen::Vector3f& c) { return 0.2126f * c.x() + 0.7152f * c.y() + 0.0722f * c.z(); }

// A frontal view of the window behind the head, before a white wall (the brightest wall: the least
// margin) 1.5 m behind (the farthest the window is sized for, where the wall shows around it):
// - the pane glows with daylight, at least kWindowOverWall times the brightest wall pixel once
//   clipped to white as the image file stores it;
// - the head is seen against it: the pixels 3 px beside the upper quarter of the subject's rows and
//   3 px above its top are window;
// - the face is lit more from behind than from the front: between the eyes it keeps under half of
//   its light under the studio's front key, while the head's outline, which the window lights from
//   behind, keeps more of its light than the face's centre (a rim);
// - the matte is the subject's whether the window is there or not (edge ties as above).
TEST(Room, WindowBehindTheHeadBacklightsIt) {
  const Subject& s = head_with_body();
  SynthOptions o = room_options(kPlainRoomLayout);
  o.width = 120, o.height = 160, o.yaw_min_deg = -3.0f, o.yaw_max_deg = 3.0f;
  o.pitch_min_deg = -2.0f, o.pitch_max_deg = 2.0f;
  const Camera cam = first_camera(s, o);
  const Eigen::Vector3f white(1, 1, 1);
  const RenderedView lit = render_plain(s, cam, 1500.0f, true, white);
  const RenderedView studio = render_plain(s, cam, 1500.0f, false, white);
  const int w = lit.rgba.width, h = lit.rgba.height;
  auto is_window = [&](int x, int y) {
    return lit.matte.at(x, y, 0) == 0.0f &&
           (rgb_at(lit, x, y) - window_daylight()).cwiseAbs().maxCoeff() < 1e-4f;
  };
  int window_px = 0, wall_px = 0, differ = 0;
  float brightest_wall = 0.0f;
  int top = h, outline_n = 0;
  double outline_keep = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float m = lit.matte.at(x, y, 0), d = std::abs(m - studio.matte.at(x, y, 0));
      EXPECT_LE(d, 1.0f / 9.0f + 1e-6f) << x << "," << y;
      differ += d > 1e-6f;
      const Eigen::Vector3f c = rgb_at(lit, x, y);
      if (m > 0.5f) top = std::min(top, y);
      if (is_window(x, y)) ++window_px;
      if (m == 0.0f && c.maxCoeff() - c.minCoeff() < 1e-4f) {  // the white wall's pixels are grey
        ++wall_px;
        brightest_wall = std::max(brightest_wall, luminance(c));
      }
    }
  EXPECT_LE(differ, int(0.001 * w * h) + 1);
  ASSERT_GT(window_px, w * h / 4);
  ASSERT_GT(wall_px, 100);
  EXPECT_GE(luminance(window_daylight().cwiseMin(1.0f)), kWindowOverWall * brightest_wall);
  // The head against the window, and its outline's light against the face's centre.
  ASSERT_LT(top, h / 3);
  const int head_rows = (h - top) / 4;
  for (int x = 0; x < w; ++x) {
    if (lit.matte.at(x, top, 0) > 0.5f) {
      EXPECT_TRUE(top >= 3 && is_window(x, top - 3)) << "above the head";
    }
  }
  for (int y = top; y < top + head_rows; ++y) {
    int x0 = w, x1 = -1;
    for (int x = 0; x < w; ++x)
      if (lit.matte.at(x, y, 0) > 0.5f) x0 = std::min(x0, x), x1 = std::max(x1, x);
    if (x1 - x0 < 6) continue;  // the crown's first rows: its outline runs nearly level there
    EXPECT_TRUE(x0 - 3 >= 0 && is_window(x0 - 3, y)) << "left of row " << y;
    EXPECT_TRUE(x1 + 3 < w && is_window(x1 + 3, y)) << "right of row " << y;
    for (int x : {x0, x1})
      if (lit.matte.at(x, y, 0) == 1.0f) {
        outline_keep += luminance(rgb_at(lit, x, y)) / luminance(rgb_at(studio, x, y));
        ++outline_n;
      }
  }
  const Eigen::Vector3f between_eyes = 0.5f * (s.landmarks.at("pupil_l") + s.landmarks.at("pupil_r"));
  float u = 0, v = 0;
  camera_project(&cam, lgn_vec3(between_eyes.x(), between_eyes.y(), between_eyes.z()), &u, &v);
  double face_keep = 0.0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int x = int(u) + dx, y = int(v) + dy;
      ASSERT_EQ(lit.matte.at(x, y, 0), 1.0f);
      face_keep += luminance(rgb_at(lit, x, y)) / luminance(rgb_at(studio, x, y)) / 9.0;
    }
  ASSERT_GT(outline_n, 10);
  EXPECT_LT(face_keep, 0.5);
  EXPECT_GT(outline_keep / outline_n, face_keep) << "no rim: the outline lost as much light as the face";
}

// The hair's pixels take the colour HeadParams::hair (synth --hair) gives them. Two heads that differ
// only in the hair's albedo, one view from behind (the brows, which mix the hair's colour with the
// skin's, out of sight): the pixels that differ are the hair's, 5 % of the subject or more; under the
// studio's white lights a pixel the hair covers fully has the hair's chromaticity exactly (light x
// albedo x the strands' shade, all grey but the albedo), so most of them (80 %: the hairline at the
// nape and beside the ears blends hair with skin) lie within 0.01 of it; the room is identical.
TEST(Room, HairTakesItsColour) {
  HeadParams p = random_head_params(0);
  p.hair = Eigen::Vector3f(0.58f, 0.19f, 0.08f);  // sRGB 200,120,80: clear of the texture's ceiling
  const Subject coloured = procedural_subject(p, HeadMeshOptions{256, 128, 512}, true);
  const Subject& usual = head_with_body();
  SynthOptions behind = room_options(kPlainRoomLayout);
  behind.yaw_min_deg = 150.0f, behind.yaw_max_deg = 180.0f;
  const Camera cam = first_camera(usual, behind);
  const Eigen::Vector3f paint = RoomPlacement{}.wall_rgb;
  const RenderedView a = render_plain(coloured, cam, 800.0f, false, paint);
  const RenderedView b = render_plain(usual, cam, 800.0f, false, paint);
  const Eigen::Vector3f hue = p.hair / p.hair.sum();
  int subject = 0, changed = 0, hair_hue = 0;
  for (int y = 0; y < a.rgba.height; ++y)
    for (int x = 0; x < a.rgba.width; ++x) {
      const Eigen::Vector3f ca = rgb_at(a, x, y), cb = rgb_at(b, x, y);
      ASSERT_EQ(a.matte.at(x, y, 0), b.matte.at(x, y, 0));
      if (a.matte.at(x, y, 0) == 0.0f) {
        EXPECT_EQ(ca, cb) << x << "," << y;
        continue;
      }
      ++subject;
      if ((ca - cb).cwiseAbs().maxCoeff() < 1e-4f) continue;
      ++changed;
      hair_hue += (ca / ca.sum() - hue).cwiseAbs().maxCoeff() < 0.01f;
    }
  EXPECT_GE(changed, subject / 20);
  EXPECT_GE(hair_hue, int(0.8 * changed)) << changed << " changed pixels";
}

TEST(Room, UnknownLayoutIsRefused) {
  EXPECT_THROW(make_room(RoomPlacement{kRoomLayouts + 1}), std::runtime_error);
}

TEST(Room, ScanRendersInARoom) {
  std::string path = std::string(LORGNETTE_DATA_DIR) + "/heads/lee-perry-smith/LeePerrySmith.glb";
  if (!fs::exists(path)) GTEST_SKIP() << "team data not found: " << path;
  Subject s = mesh_subject(path);
  SynthOptions o = room_options(1);
  RenderedView v = render_in_room(s, 1, first_camera(s, o));
  double cover = 0;
  for (float m : v.matte.pixels) cover += m;
  cover /= v.matte.pixels.size();
  EXPECT_GT(cover, 0.1);
  EXPECT_LT(cover, 0.8) << "the room should be seen around the scan";
}

}  // namespace
}  // namespace lorgnette::synth
