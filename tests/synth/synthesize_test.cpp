// Tests of dataset synthesis: the written dataset round-trips through the dataset loader, the depth
// EXR and the cameras (a pixel's depth reprojects onto the mesh point its ray hits, sub-pixel), the
// ground truth matches the subject, the output appears atomically (non-empty directories refused,
// nothing left behind on errors or Ctrl-C), and the team's real head meshes load and render.
#include "synth/synthesize.h"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "host/dataset/dataset.h"
#include "host/util/interrupt.h"
#include "mesh/embree_scene.h"
#include "test_head.h"

namespace lorgnette::synth {
namespace {

namespace fs = std::filesystem;

std::string tmp(const std::string& name) {
  fs::path p = fs::path(LORGNETTE_TEST_TMP) / "synth" / name;
  fs::remove_all(p);
  fs::create_directories(p.parent_path());
  return p.string();
}

SynthOptions small_options() {
  SynthOptions o;
  o.views = 3;
  o.width = 80, o.height = 64;
  o.samples_per_axis = 2;
  o.seed = 5;
  return o;
}

TEST(Synthesize, DatasetRoundTripsThroughLoaderDepthAndCameras) {
  const Subject& s = test::default_head();
  std::string dir = tmp("roundtrip");
  SynthReport r = synthesize_dataset(s, dir, small_options());
  EXPECT_EQ(r.views, 3);
  dataset::Dataset ds = dataset::load_dataset(dir);
  ASSERT_EQ(ds.frames.size(), 3u);
  ASSERT_TRUE(ds.mm_per_unit.has_value());
  EXPECT_DOUBLE_EQ(*ds.mm_per_unit, kProceduralMmPerUnit);
  // The mesh in the dataset frame, rebuilt from ground_truth.json's transform.
  Eigen::Matrix4f m;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m(i, j) = ds.ground_truth.at("mesh_to_dataset")[i][j].get<float>();
  mesh::EmbreeScene scene(s.mesh, m);
  nlohmann::json tj = nlohmann::json::parse(std::ifstream(dir + "/transforms.json"));
  int checked = 0;
  for (size_t f = 0; f < ds.frames.size(); ++f) {
    const Camera& cam = ds.frames[f].camera;
    EXPECT_EQ(ds.frames[f].image.width, 80);
    Image depth = read_image(dir + "/" + tj["frames"][f]["depth_path"].get<std::string>());
    ASSERT_EQ(depth.width, 80);
    LgnVec3 o = camera_origin(&cam);
    Eigen::Vector3f origin(o.x, o.y, o.z);
    for (int y = 2; y < 64; y += 7)
      for (int x = 3; x < 80; x += 7) {
        float t = depth.at(x, y, 0);
        LgnVec3 d = camera_ray_dir(&cam, x + 0.5f, y + 0.5f);
        Eigen::Vector3f dir3(d.x, d.y, d.z);
        mesh::Hit h = scene.intersect(origin, dir3);
        ASSERT_EQ(h.hit, std::isfinite(t)) << "frame " << f << " pixel " << x << "," << y;
        if (!h.hit) continue;
        // Reprojection: the depth point is the mesh hit (1e-4 units = 0.02 mm: float round-off of
        // the EXR's 32-bit depth at distance ~3) and projects back to the pixel centre (1e-3 px).
        Eigen::Vector3f p = origin + t * dir3;
        EXPECT_LT((p - h.position).norm(), 1e-4f);
        float u, v;
        camera_project(&cam, lgn_vec3(p.x(), p.y(), p.z()), &u, &v);
        EXPECT_NEAR(u, x + 0.5f, 1e-3);
        EXPECT_NEAR(v, y + 0.5f, 1e-3);
        // Alpha is coverage: a pixel whose centre hits the head is at least partly covered.
        EXPECT_GT(ds.frames[f].image.at(x, y, 3), 0.0f);
        ++checked;
      }
  }
  EXPECT_GT(checked, 50);
  // Ground truth landmarks are the subject's, in the dataset frame.
  auto tip = ds.ground_truth.at("landmarks").at("nose_tip");
  EXPECT_NEAR(tip[2].get<float>(), s.landmarks.at("nose_tip").z(), 1e-6);
  EXPECT_EQ(ds.ground_truth.at("ibug68").size(), 68u);
  EXPECT_EQ(ds.ground_truth.at("source"), "procedural");
}

TEST(Synthesize, OpaqueBackgroundHasFullAlphaAndTheColour) {
  std::string dir = tmp("opaque");
  SynthOptions o = small_options();
  o.views = 1;
  o.background = Eigen::Vector3f(0.0f, 1.0f, 0.0f);
  synthesize_dataset(test::default_head(), dir, o);
  Image img = read_image(dir + "/images/0000.png");
  ASSERT_EQ(img.channels, 4);
  EXPECT_FLOAT_EQ(img.at(0, 0, 3), 1.0f);
  EXPECT_NEAR(img.at(0, 0, 1), 1.0f, 1e-3);  // the corner sees the background
  EXPECT_NEAR(img.at(0, 0, 0), 0.0f, 1e-3);
}

// --force replaces only an earlier synth output: a folder of other files is refused even with it.
TEST(Synthesize, ForceReplacesOnlyAnEarlierSynthOutput) {
  std::string dir = tmp("nonempty");
  fs::create_directories(dir);
  std::ofstream(dir + "/keep.txt") << "user data";
  SynthOptions o = small_options();
  o.views = 1;
  EXPECT_THROW(synthesize_dataset(test::default_head(), dir, o), std::runtime_error);
  o.force = true;
  EXPECT_THROW(synthesize_dataset(test::default_head(), dir, o), std::runtime_error);
  EXPECT_TRUE(fs::exists(dir + "/keep.txt"));
  EXPECT_FALSE(fs::exists(dir + "/transforms.json"));

  std::string earlier = tmp("earlier");
  o.force = false;
  synthesize_dataset(test::default_head(), earlier, o);
  EXPECT_THROW(synthesize_dataset(test::default_head(), earlier, o), std::runtime_error);
  std::ofstream(earlier + "/stale.txt") << "from the earlier output";
  o.force = true;
  synthesize_dataset(test::default_head(), earlier, o);
  EXPECT_TRUE(fs::exists(earlier + "/transforms.json"));
  EXPECT_FALSE(fs::exists(earlier + "/stale.txt")) << "the earlier output is replaced as a whole";
}

TEST(Synthesize, UnwritableOutputFailsCleanly) {
  SynthOptions o = small_options();
  o.views = 1;
  EXPECT_THROW(synthesize_dataset(test::default_head(), "/proc/lorgnette-no-such/out", o),
               std::runtime_error);
}

TEST(Synthesize, CtrlCLeavesNothingBehind) {
  std::string dir = tmp("interrupted");
  install_interrupt_handler();
  SynthOptions o = small_options();
  o.progress = [](int done, int) {
    if (done == 1) std::raise(SIGINT);
  };
  EXPECT_THROW(synthesize_dataset(test::default_head(), dir, o), std::runtime_error);
  clear_interrupt();
  EXPECT_FALSE(fs::exists(dir));
  for (const auto& e : fs::directory_iterator(fs::path(dir).parent_path()))
    EXPECT_EQ(e.path().filename().string().find(".interrupted.partial"), std::string::npos) << e.path();
}

void render_real_mesh(const std::string& rel) {
  std::string path = std::string(LORGNETTE_DATA_DIR) + "/" + rel;
  if (!fs::exists(path)) GTEST_SKIP() << "team data not found: " << path;
  Subject s = mesh_subject(path);
  EXPECT_FALSE(s.mm_per_unit.has_value());
  SynthOptions o = small_options();
  o.views = 1;
  o.yaw_min_deg = o.yaw_max_deg = 0.0f;
  o.pitch_min_deg = o.pitch_max_deg = 0.0f;
  mesh::EmbreeScene scene(s.mesh, s.mesh_to_dataset);
  Camera cam = make_camera_rig(rig_for(s, o))[0].camera;
  RenderedView v = render_view(scene, cam, StudioLighting{}, RenderSettings{1, std::nullopt, 0});
  double cover = 0, lum = 0;
  for (int y = 0; y < v.rgba.height; ++y)
    for (int x = 0; x < v.rgba.width; ++x) {
      cover += v.rgba.at(x, y, 3);
      lum += v.rgba.at(x, y, 3) * v.rgba.at(x, y, 1);
    }
  double frac = cover / (v.rgba.width * v.rgba.height);
  EXPECT_GT(frac, 0.1) << rel << " covers too little of the frame";
  EXPECT_LT(frac, 0.95) << rel;
  EXPECT_GT(lum / cover, 0.02) << rel << " renders black (texture or lighting missing)";
}

TEST(Synthesize, LeePerrySmithLoadsAndRenders) {
  render_real_mesh("heads/lee-perry-smith/LeePerrySmith.glb");
}
TEST(Synthesize, NefertitiLoadsAndRenders) { render_real_mesh("meshes/Nefertiti.glb"); }

}  // namespace
}  // namespace lorgnette::synth
