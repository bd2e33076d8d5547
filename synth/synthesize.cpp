// Dataset synthesis; see synthesize.h. Images and depth maps are written into the staging
// directory as each view finishes; transforms.json (through the dataset module's writer) and
// ground_truth.json come last, and the directory is renamed into place only after all of them.
#include "synth/synthesize.h"

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "host/dataset/dataset.h"
#include "host/util/interrupt.h"
#include "host/util/output_folder.h"
#include "mesh/embree_scene.h"
#include "synth/card.h"
#include "synth/matte.h"
#include "synth/room.h"

namespace lorgnette::synth {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

const OutputOwner kSynthOutput{"synth", "synthetic dataset", ""};

json vec_json(const Eigen::Vector3f& v) { return json::array({v.x(), v.y(), v.z()}); }

json matrix_json(const Eigen::Matrix4f& m) {
  json rows = json::array();
  for (int r = 0; r < 4; ++r) rows.push_back({m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
  return rows;
}

RoomPlacement plain_placement(const SynthOptions& o) {
  RoomPlacement plain;
  plain.wall_mm = o.wall_mm, plain.wall_rgb = o.wall_rgb, plain.window = o.window;
  return plain;
}

// The window's pane in the room's millimetres about the eye point (the dataset frame's axes).
json window_json(float wall_mm) {
  const WindowRect& w = kWindowMm;
  return {{"x_mm", {w.x0, w.x1}},
          {"y_mm", {w.y0, w.y1}},
          {"z_mm", -wall_mm + kWindowPaneMm},
          {"radiance_linear", vec_json(window_daylight())},
          {"note", "emissive pane in the wall, the key light's source (lighting)"}};
}

void check_options(const SynthOptions& o) {
  if (o.samples_per_axis < 1 || o.samples_per_axis > 16)
    throw std::runtime_error(
        fmt::format("synth: samples per axis {} is out of range (1..16)", o.samples_per_axis));
  if (o.room < 0 || o.room > kRoomLayouts)
    throw std::runtime_error(
        fmt::format("synth: room layout {} does not exist; use 1..{} (0 = no room)", o.room, kRoomLayouts));
  if (o.room > 0 && !(o.fov_y_deg > 10.0f && o.fov_y_deg < 120.0f))
    throw std::runtime_error(
        fmt::format("synth: field of view {} deg is out of range (10..120)", o.fov_y_deg));
  if (o.window && o.room != kPlainRoomLayout)
    throw std::runtime_error(
        fmt::format("synth: the window lies in the plain room's wall: give --room {}", kPlainRoomLayout));
  if (o.card && o.room == 0)
    throw std::runtime_error("synth: the card is held in a room capture: give --room 1..3 with --card");
  if (o.background && (o.background->minCoeff() < 0.0f || o.background->maxCoeff() > 1.0f))
    throw std::runtime_error("synth: background colour components must lie in [0, 1]");
}

json ground_truth_json(const Subject& s, const SynthOptions& o, const std::vector<RigView>& views) {
  json gt;
  gt["version"] = 1;
  gt["source"] = s.source;
  if (s.source == "procedural") {
    gt["seed"] = s.params.value("seed", uint64_t(0));
    gt["params"] = s.params;
    gt["mesh_units"] = "mm";
  }
  gt["mesh_to_dataset"] = matrix_json(s.mesh_to_dataset);
  gt["mm_per_unit"] = s.mm_per_unit ? json(*s.mm_per_unit) : json(nullptr);
  if (s.metric.is_object())
    for (const auto& [key, value] : s.metric.items()) gt[key] = value;
  json lm = json::object();
  for (const auto& [name, p] : s.landmarks) lm[name] = vec_json(p);
  gt["landmarks"] = lm;
  json ibug = json::array();
  for (const auto& p : s.ibug68) ibug.push_back(vec_json(p));
  gt["ibug68"] = ibug;
  gt["ibug68_note"] =
      "points 0-16 are the face contour of a frontal view (view dependent); 17-67 lie on painted features";
  gt["depth"] = {{"kind", "ray_distance"},
                 {"units", "dataset"},
                 {"miss", "inf"},
                 {"note", "distance along the unit-length ray through the pixel centre"}};
  gt["camera_seed"] = o.seed;
  gt["look_at"] = vec_json(s.look_at);
  json vj = json::array();
  for (size_t i = 0; i < views.size(); ++i)
    vj.push_back({{"file", fmt::format("images/{:04d}.png", i)},
                  {"yaw_deg", views[i].yaw_deg},
                  {"pitch_deg", views[i].pitch_deg}});
  gt["views"] = vj;
  const StudioLighting l = room_lighting(plain_placement(o), o.lighting);
  gt["lighting"] = {
      {"model", l.specular > 0.0f ? "lambert + blinn-phong highlight on the subject" : "lambert"},
      {"key_dir", vec_json(l.key_dir.normalized())},
      {"key", l.key},
      {"key_radius_deg", l.key_radius_deg},
      {"fill_dir", vec_json(l.fill_dir.normalized())},
      {"fill", l.fill},
      {"sky", l.sky},
      {"ground", l.ground},
      {"shadows", l.shadows},
      {"specular", l.specular},
      {"shininess", l.shininess}};
  gt["render"] = {{"samples_per_pixel", o.samples_per_axis * o.samples_per_axis},
                  {"background", o.background ? vec_json(*o.background) : json("transparent")}};
  if (o.room > 0) {
    gt["room"] = {{"layout", o.room},
                  {"mm_per_unit", s.room_mm_per_unit},
                  {"eye_point", vec_json(s.eye_point)},
                  {"cameras", "hand-held sweep"},
                  {"wall_mm", o.room == kPlainRoomLayout ? json(o.wall_mm) : json()},
                  {"wall_rgb", o.room == kPlainRoomLayout ? vec_json(o.wall_rgb) : json()},
                  {"window", o.window ? window_json(o.wall_mm) : json()},
                  {"fov_y_deg", o.fov_y_deg},
                  {"distance_mm", o.phone_distance_mm},
                  {"mattes", "mattes/NNNN.png: subject coverage 0..255 (not sRGB); frames' eval_matte_path"},
                  {"depth_note", "depth counts the subject only (inf where the room is seen)"}};
  }
  return gt;
}

// Adds per-frame depth_path (instant-ngp's key) and, with mattes, eval_matte_path to the
// transforms.json the dataset writer produced.
void add_depth_paths(const std::string& dir, size_t count, bool mattes) {
  fs::path p = fs::path(dir) / "transforms.json";
  json tj = json::parse(std::ifstream(p));
  for (auto& f : tj.at("frames")) {
    std::string img = f.at("file_path");
    f["depth_path"] = "depth/" + fs::path(img).stem().string() + ".exr";
    if (mattes) f["eval_matte_path"] = "mattes/" + fs::path(img).stem().string() + ".png";
  }
  if (tj.at("frames").size() != count)
    throw std::runtime_error("synth: transforms.json frame count mismatch");
  write_text_file_atomic(p.string(), tj.dump(2) + "\n");
}

// The scenes a capture's views are rendered from: the subject alone (in its room), and with a card,
// also the card held and the card under either finger; view_scene[i] picks view i's.
struct SceneSet {
  std::vector<std::unique_ptr<mesh::EmbreeScene>> scenes;
  std::vector<int> view_scene;
  std::optional<HeldCard> card;  // dataset frame (millimetres scaled to dataset units)
  int subject_triangles = -1;
};

const char* const kSceneNames[] = {"none", "none", "lower_edge", "lower_right_corner"};

// Scene index of view i with a card: 1 card, 2 finger over the lower edge, 3 over the corner.
int card_scene_of_view(int i, int views) {
  if (i >= (views + 1) / 2) return 0;
  return i % 4 == 1 ? 2 : (i % 4 == 3 ? 3 : 1);
}

HeldCard card_in_dataset(const HeldCard& mm, const Eigen::Matrix4f& to_dataset) {
  HeldCard d;
  for (int k = 0; k < 4; ++k) d.corners[k] = transform_point(to_dataset, mm.corners[k]);
  d.normal = (to_dataset.topLeftCorner<3, 3>() * mm.normal).normalized();
  return d;
}

// The card on the subject's forehead (millimetres) and the map from those millimetres to the dataset
// frame. The procedural head's own frame is in millimetres and its brows' height is known; a mesh's
// forehead is found from its shape (card.h) in the dataset frame scaled to millimetres, which needs
// the mesh's millimetres (checked before anything is rendered).
struct PlacedCard {
  HeldCard mm;
  Eigen::Matrix4f mm_to_dataset;
};

PlacedCard card_on_subject(const Subject& s) {
  // The card's lower edge 6 mm above the brows (the procedural head's brows' peak, a scan's
  // glabella), clear of the brows and the eyes.
  if (s.source == "procedural")
    return {card_on_forehead(s.mesh, s.params.at("brow_height").get<float>() + 6.0f), s.mesh_to_dataset};
  const float mm = float(*s.mm_per_unit);
  Eigen::Matrix4f to_mm = Eigen::Matrix4f::Identity(), mm_to_dataset = Eigen::Matrix4f::Identity();
  to_mm.topLeftCorner<3, 3>() *= mm;
  mm_to_dataset.topLeftCorner<3, 3>() *= 1.0f / mm;
  return {card_on_scanned_forehead(s.mesh, to_mm * s.mesh_to_dataset, 6.0f), mm_to_dataset};
}

SceneSet make_scenes(const Subject& subject, const SynthOptions& o, const std::vector<RigView>& views) {
  SceneSet set;
  set.view_scene.assign(views.size(), 0);
  if (o.room == 0) {
    set.scenes.push_back(std::make_unique<mesh::EmbreeScene>(subject.mesh, subject.mesh_to_dataset));
    return set;
  }
  RoomScene room = subject_in_room(subject, o.room, plain_placement(o));
  set.subject_triangles = room.subject_triangles;
  if (o.card) {
    const PlacedCard card = card_on_subject(subject);
    set.card = card_in_dataset(card.mm, card.mm_to_dataset);
    mesh::TriMesh with_card = room.mesh;
    append_mesh(with_card, card_mesh(card.mm), card.mm_to_dataset);
    for (FingerPlacement f : {FingerPlacement::LowerEdge, FingerPlacement::LowerRightCorner}) {
      mesh::TriMesh m = with_card;
      append_mesh(m, finger_mesh(card.mm, f), card.mm_to_dataset);
      set.scenes.push_back(std::make_unique<mesh::EmbreeScene>(std::move(m)));
    }
    set.scenes.insert(set.scenes.begin(), std::make_unique<mesh::EmbreeScene>(std::move(with_card)));
    for (size_t i = 0; i < views.size(); ++i)
      set.view_scene[i] = card_scene_of_view(int(i), int(views.size()));
  }
  set.scenes.insert(set.scenes.begin(), std::make_unique<mesh::EmbreeScene>(std::move(room.mesh)));
  return set;
}

// ground_truth.json "card": the corners in the dataset frame and, per view that shows the card,
// their pixel positions (continuous coordinates, pixel centres at i + 0.5) and the finger's place.
json card_json(const HeldCard& card, const std::vector<RigView>& views, const std::vector<int>& view_scene) {
  json corners = json::array(), frames = json::array();
  for (const auto& c : card.corners) corners.push_back(vec_json(c));
  for (size_t i = 0; i < views.size(); ++i) {
    if (view_scene[i] == 0) continue;
    json px = json::array();
    for (const auto& c : card.corners) {
      float u = 0, v = 0;
      camera_project(&views[i].camera, lgn_vec3(c.x(), c.y(), c.z()), &u, &v);
      px.push_back({u, v});
    }
    frames.push_back({{"file", fmt::format("images/{:04d}.png", i)},
                      {"index", i},
                      {"finger", kSceneNames[view_scene[i]]},
                      {"corners_px", px}});
  }
  return {{"size_mm", {kCardWidthMm, kCardHeightMm}},
          {"corners", corners},
          {"corner_order", "top-left, top-right, bottom-right, bottom-left seen from the front"},
          {"normal", vec_json(card.normal)},
          {"frames", frames}};
}

}  // namespace

RoomScene subject_in_room(const Subject& subject, int layout, const RoomPlacement& plain) {
  RoomScene out;
  append_mesh(out.mesh, subject.mesh, subject.mesh_to_dataset);
  out.subject_triangles = int(out.mesh.triangles.size());
  RoomPlacement placement = plain;
  placement.layout = layout;
  placement.mm_to_dataset = Eigen::Matrix4f::Identity();
  placement.mm_to_dataset.topLeftCorner<3, 3>() *= float(1.0 / subject.room_mm_per_unit);
  placement.mm_to_dataset.topRightCorner<3, 1>() = subject.eye_point;
  append_mesh(out.mesh, make_room(placement), Eigen::Matrix4f::Identity());
  return out;
}

RigOptions rig_for(const Subject& subject, const SynthOptions& o) {
  RigOptions rig;
  rig.views = o.views;
  rig.width = o.width, rig.height = o.height;
  rig.yaw_min_deg = o.yaw_min_deg, rig.yaw_max_deg = o.yaw_max_deg;
  rig.pitch_min_deg = o.pitch_min_deg, rig.pitch_max_deg = o.pitch_max_deg;
  rig.seed = o.seed;
  rig.target = subject.look_at;
  rig.distance = o.camera_distance;
  rig.frame_radius = subject.frame_radius;
  if (o.room > 0) {
    rig.handheld = true;
    rig.fov_y_deg = o.fov_y_deg;
    rig.distance = float(o.phone_distance_mm / subject.room_mm_per_unit);
  }
  return rig;
}

SynthReport synthesize_dataset(const Subject& subject, const std::string& out_dir, const SynthOptions& o) {
  auto t0 = std::chrono::steady_clock::now();
  check_options(o);
  if (o.card && !subject.mm_per_unit)
    throw std::runtime_error(
        "synth: --card with --mesh needs --mesh-mm-per-unit: the card is 85.60 x 53.98 mm, a size "
        "that means nothing without the mesh's millimetres (give the millimetres per mesh unit)");
  std::vector<RigView> views = make_camera_rig(rig_for(subject, o));
  std::vector<std::string> inputs;  // a mesh file inside the output folder is refused
  if (subject.source != "procedural") inputs.push_back(subject.source);
  StagedOutput staged(out_dir, kSynthOutput, o.force, inputs);
  fs::create_directories(fs::path(staged.path()) / "images");
  fs::create_directories(fs::path(staged.path()) / "depth");
  if (o.room > 0) fs::create_directories(fs::path(staged.path()) / "mattes");
  RenderSettings settings{o.samples_per_axis, o.background, 0};
  SceneSet scenes = make_scenes(subject, o, views);
  const StudioLighting lighting = room_lighting(plain_placement(o), o.lighting);
  if (o.room > 0) {
    settings.subject_triangles = scenes.subject_triangles;
    if (!settings.background) settings.background = room_sky();
  }
  SynthReport report;
  std::vector<Camera> cameras;
  std::vector<std::string> files;
  for (size_t i = 0; i < views.size(); ++i) {
    if (interrupted())
      throw std::runtime_error("synth: interrupted; nothing was written to the output directory");
    auto r0 = std::chrono::steady_clock::now();
    const mesh::EmbreeScene& scene = *scenes.scenes[size_t(scenes.view_scene[i])];
    RenderedView v = render_view(scene, views[i].camera, lighting, settings);
    report.render_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - r0).count();
    std::string name = fmt::format("{:04d}", i);
    if (o.room > 0) {
      Image rgb(v.rgba.width, v.rgba.height, 3);
      for (size_t p = 0; p < size_t(rgb.width) * rgb.height; ++p)
        for (int c = 0; c < 3; ++c) rgb.pixels[p * 3 + c] = v.rgba.pixels[p * 4 + c];
      write_image(staged.path() + "/images/" + name + ".png", rgb);
      write_matte(staged.path() + "/mattes/" + name + ".png", v.matte);
    } else {
      write_image(staged.path() + "/images/" + name + ".png", v.rgba);
    }
    write_image(staged.path() + "/depth/" + name + ".exr", v.depth);
    cameras.push_back(views[i].camera);
    files.push_back("images/" + name + ".png");
    if (o.progress) o.progress(int(i + 1), int(views.size()));
  }
  json extra = {
      {"aabb_scale", 1}, {"scale", 0.33}, {"offset", {0.5, 0.5, 0.5}}, {"synthetic", "lorgnette synth"}};
  dataset::write_transforms_json(staged.path(), cameras, files, extra);
  add_depth_paths(staged.path(), files.size(), o.room > 0);
  json gt = ground_truth_json(subject, o, views);
  if (scenes.card) gt["card"] = card_json(*scenes.card, views, scenes.view_scene);
  write_text_file_atomic(staged.path() + "/ground_truth.json", gt.dump(2) + "\n");
  if (interrupted())
    throw std::runtime_error("synth: interrupted; nothing was written to the output directory");
  staged.commit();
  report.directory = fs::absolute(out_dir).lexically_normal().string();
  report.views = int(views.size());
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace lorgnette::synth
