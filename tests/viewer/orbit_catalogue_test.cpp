// Orbit limits from a capture's cameras, clamping, the orbit camera's geometry and row crops; the
// catalogue listing, nudges and safe saving (refuse without confirmation, backup when replacing).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <tuple>

#include "fit/placement_json.h"
#include "viewer/catalogue.h"
#include "viewer/orbit_control.h"

namespace {

using namespace lorgnette;
using namespace lorgnette::viewer;
namespace fs = std::filesystem;

fs::path tmp_dir(const std::string& name) {
  fs::path p = fs::path(LORGNETTE_TEST_TMP) / "viewer-unit" / name;
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

// An orbit spec round a sphere of `radius` (half extents along x only) at `center`.
render::OrbitSpec sphere_spec(render::Vec3 center, float radius, render::Vec3 front, render::Vec3 up) {
  render::OrbitSpec s;
  s.center = center, s.half_extent = {radius, 0, 0}, s.front = front, s.up = up;
  return s;
}

Camera camera_at(float yaw_deg, float pitch_deg, float dist) {
  const float k = 3.14159265f / 180.0f;
  return render::look_at(
      {dist * std::cos(pitch_deg * k) * std::sin(yaw_deg * k), dist * std::sin(pitch_deg * k),
       dist * std::cos(pitch_deg * k) * std::cos(yaw_deg * k)},
      {0, 0, 0}, {0, 1, 0}, 64, 64, 30.0f);
}

TEST(ViewerOrbit, LimitsFollowTheCaptureCamerasWithAMargin) {
  // Each yaw filmed from +10 and -10 deg of pitch: the mean up is +y and the mean front +z exactly.
  std::vector<Camera> cams;
  for (float yaw = -35; yaw <= 35; yaw += 5)
    for (float pitch : {-10.0f, 10.0f}) cams.push_back(camera_at(yaw, pitch, 3.0f));
  OrbitLimits l = limits_from_range(nerf::view_range_from_cameras(cams, {0, 0, 0}), 5.0, 20.0);
  // Tolerance 0.01 deg: float camera positions.
  EXPECT_NEAR(l.yaw_min, -40.0, 0.01);
  EXPECT_NEAR(l.yaw_max, 40.0, 0.01);
  EXPECT_NEAR(l.pitch_min, -15.0, 0.01);
  EXPECT_NEAR(l.pitch_max, 15.0, 0.01);
  EXPECT_NE(l.source.find("30 cameras"), std::string::npos);
  // No range: the default +-60 / +-30.
  OrbitLimits d = limits_from_range(std::nullopt);
  EXPECT_EQ(d.yaw_max, 60.0);
  EXPECT_EQ(d.pitch_min, -30.0);
  EXPECT_EQ(d.source, "default");
}

TEST(ViewerOrbit, NarrowCapturesStillGetAMinimumSpan) {
  OrbitLimits l =
      limits_from_range(nerf::view_range_from_cameras({camera_at(0, 0, 3)}, {0, 0, 0}), 2.0, 20.0);
  EXPECT_NEAR(l.yaw_max - l.yaw_min, 20.0, 1e-6);
  EXPECT_NEAR(l.pitch_max - l.pitch_min, 20.0, 1e-6);
}

TEST(ViewerOrbit, ClampKeepsTheStateInsideTheLimits) {
  OrbitLimits l;
  OrbitState s = clamp_orbit({170, -80, 9, 5, -5}, l);
  EXPECT_EQ(s.yaw_deg, l.yaw_max);
  EXPECT_EQ(s.pitch_deg, l.pitch_min);
  EXPECT_EQ(s.distance, l.distance_max);
  EXPECT_EQ(s.pan_x, l.pan_max);
  EXPECT_EQ(s.pan_y, -l.pan_max);
}

TEST(ViewerOrbit, CameraLooksAtTheCentreFromTheYawedDirection) {
  OrbitFrame f = make_orbit_frame(sphere_spec({1, 2, 3}, 0.5f, {0, 0, 1}, {0, 1, 0}));
  Camera c = orbit_camera(f, {90, 0, 1, 0, 0}, 64, 48);
  // yaw +90: the camera sits on +right (= +x for front +z, up +y) and looks back at the centre.
  EXPECT_GT(c.c2w[3], 1.5f);
  EXPECT_NEAR(c.c2w[7], 2.0f, 1e-4);
  EXPECT_NEAR(c.c2w[11], 3.0f, 1e-4);
  LgnVec3 d = camera_ray_dir(&c, 32, 24);
  EXPECT_NEAR(d.x, -1.0f, 1e-3);
}

// The viewer frames the head as `render --orbit` does (one orbit request, render::OrbitSettings): its
// start state is the orbit's first camera, for any field of view, margin, image shape, and a front
// and up that are not orthogonal. Tolerance: float rounding of two equal constructions (1e-5).
TEST(ViewerOrbit, StartViewIsTheRenderOrbitsFirstCamera) {
  render::OrbitSpec spec = sphere_spec({0.2f, -0.1f, 0.3f}, 0.7f, {0.3f, 0.2f, 1.0f}, {0.1f, 1.0f, 0.4f});
  for (auto [fov, margin, w, h] : {std::tuple{30.0f, 1.05f, 64u, 48u}, std::tuple{50.0f, 1.3f, 40u, 90u}}) {
    spec.fov_y_deg = fov, spec.margin = margin, spec.width = w, spec.height = h;
    Camera viewer = orbit_camera(make_orbit_frame(spec), {0, 0, 1, 0, 0}, w, h);
    Camera cli = render::orbit_cameras(spec).at(0);
    for (int i = 0; i < 12; ++i) EXPECT_NEAR(viewer.c2w[i], cli.c2w[i], 1e-5) << "c2w[" << i << "]";
    EXPECT_NEAR(viewer.fy, cli.fy, 1e-3);
    EXPECT_NEAR(viewer.fx, cli.fx, 1e-3);
  }
}

TEST(ViewerOrbit, RowCropsRenderTheSameRaysAsTheFullCamera) {
  OrbitFrame f = make_orbit_frame(sphere_spec({0, 0, 0}, 1.0f, {0, 0, 1}, {0, 1, 0}));
  Camera full = orbit_camera(f, {10, 5, 1, 0, 0}, 80, 60);
  Camera band = crop_rows(full, 24, 12);
  EXPECT_EQ(band.height, 12u);
  LgnVec3 a = camera_ray_dir(&full, 10.5f, 24 + 3.5f), b = camera_ray_dir(&band, 10.5f, 3.5f);
  EXPECT_NEAR(a.x, b.x, 1e-6);
  EXPECT_NEAR(a.y, b.y, 1e-6);
  EXPECT_NEAR(a.z, b.z, 1e-6);
}

TEST(ViewerCatalogue, ListsFramesAndSingleFileFolders) {
  fs::path d = tmp_dir("catalogue");
  std::ofstream(d / "b.glb") << "x";
  std::ofstream(d / "a.OBJ") << "x";
  std::ofstream(d / "notes.txt") << "x";
  std::ofstream(d / "a.OBJ.placement.json") << "{}";
  fs::create_directories(d / "c-folder");
  std::ofstream(d / "c-folder" / "scene.gltf") << "x";
  fs::create_directories(d / "two");
  std::ofstream(d / "two" / "x.glb") << "x";
  std::ofstream(d / "two" / "y.glb") << "x";
  auto c = catalogue_from_dir(d.string());
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0].name, "a.OBJ");
  EXPECT_EQ(c[1].name, "b.glb");
  EXPECT_EQ(c[2].name, "c-folder");
  EXPECT_EQ(fs::path(c[2].path).filename(), "scene.gltf");
  EXPECT_TRUE(existing_placement(c[0]).has_value());
  EXPECT_FALSE(existing_placement(c[1]).has_value());
  EXPECT_THROW(catalogue_from_dir((d / "two" / "none").string()), std::runtime_error);
}

TEST(ViewerCatalogue, NudgesAccumulateWithinBoundsAndActInTheFramesAxes) {
  Nudge n = accumulate({}, NudgeMsg{2, -1, 3, false});
  n = accumulate(n, NudgeMsg{2, 0, 0, false});
  EXPECT_DOUBLE_EQ(n.up_mm, 4);
  EXPECT_DOUBLE_EQ(n.forward_mm, -1);
  EXPECT_DOUBLE_EQ(n.tilt_deg, 3);
  for (int i = 0; i < 10; ++i) n = accumulate(n, NudgeMsg{10, 0, 10, false});
  EXPECT_DOUBLE_EQ(n.up_mm, kMaxNudgeMm);
  EXPECT_DOUBLE_EQ(n.tilt_deg, kMaxNudgeTiltDeg);
  EXPECT_TRUE(accumulate(n, NudgeMsg{0, 0, 0, true}).zero());
  // Up 2 mm on a frame scaled 0.01 scene units per mm and turned 90 deg about z: +y canonical maps to -x
  // scene.
  Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
  t.block<3, 3>(0, 0) << 0, -0.01, 0, 0.01, 0, 0, 0, 0, 0.01;
  Eigen::Vector4d p = t * nudge_matrix({2, 0, 0}) * Eigen::Vector4d(0, 0, 0, 1);
  EXPECT_NEAR(p.x(), -0.02, 1e-12);
  EXPECT_NEAR(p.y(), 0.0, 1e-12);
  // Tilt keeps the bridge (the origin) fixed; positive tilt turns a point below it (-y) backwards (-z).
  Eigen::Vector4d below = nudge_matrix({0, 0, 10}) * Eigen::Vector4d(0, -20, 0, 1);
  EXPECT_LT(below.z(), 0.0) << "positive tilt brings the lenses' bottoms towards the face (-z)";
}

TEST(ViewerCatalogue, SavingRefusesToReplaceWithoutConfirmationAndKeepsABackup) {
  fs::path d = tmp_dir("save");
  std::string path = (d / "frame.glb.placement.json").string();
  fit::PlacementFile p;
  p.transform(0, 3) = 1.5;
  SaveResult first = save_placement(path, p, {}, false);
  ASSERT_TRUE(first.ok) << first.error.message;
  EXPECT_TRUE(first.backup.empty());
  std::ofstream(path, std::ios::app) << " ";  // the user's edits
  SaveResult refused = save_placement(path, p, {1, 0, 0}, false);
  EXPECT_FALSE(refused.ok);
  EXPECT_EQ(refused.error.code, "exists");
  SaveResult replaced = save_placement(path, p, {1, 0, 0}, true);
  ASSERT_TRUE(replaced.ok) << replaced.error.message;
  ASSERT_FALSE(replaced.backup.empty());
  EXPECT_TRUE(fs::exists(replaced.backup));
  fit::PlacementFile back = fit::read_placement(path);
  EXPECT_NEAR(back.transform(1, 3), 1.0, 1e-9);  // identity rotation and scale: up 1 mm = +1 in y
  EXPECT_NEAR(back.transform(0, 3), 1.5, 1e-9);
  // The nudge is the format's own field (no side object the reader does not know).
  ASSERT_TRUE(back.has_nudge);
  EXPECT_EQ(back.nudge.up_mm, 1.0);
  std::ifstream in(path);
  nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_FALSE(j.contains("viewer"));
  EXPECT_EQ(j["nudge"]["up_mm"], 1.0);
  // A second nudge saved onto the saved file: the record sums both (here: 1 + 0.5 mm up).
  ASSERT_TRUE(save_placement(path, back, {0.5, 0, 0}, true).ok);
  EXPECT_NEAR(fit::read_placement(path).nudge.up_mm, 1.5, 1e-12);
  EXPECT_NEAR(fit::read_placement(path).transform(1, 3), 1.5, 1e-9);
}

}  // namespace
