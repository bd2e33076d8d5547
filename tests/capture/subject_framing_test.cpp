// Bad input that keeps the subject from being separated (issue #13): the head's framing check
// (capture/subject_framing.h) on a known head box seen from near (the head fills and overflows every
// frame) and from arm's length; a capture with some good frames passes. The problem a training run
// records travels in the .lnerf snapshot, so the fit can refuse the model.
#include "capture/subject_framing.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "host/nerf/snapshot.h"

namespace lorgnette::capture {
namespace {

// A head box the size of an adult's (170 x 340 x 250 mm at 1 unit = 1 m), facing +z.
fit::HeadBox head() {
  fit::HeadBox b;
  b.center = Eigen::Vector3d(0.1, 1.6, -0.2);
  b.half_extent = Eigen::Vector3d(0.105, 0.17, 0.13);
  b.min = b.center - b.half_extent, b.max = b.center + b.half_extent;
  return b;
}

// A 1080x1920 portrait phone camera (vertical field of view 65 deg) `dist` metres in front of the
// head at `yaw` degrees, aimed at its eye level.
Camera phone(double dist, double yaw) {
  fit::HeadBox b = head();
  double k = 3.14159265358979 / 180.0;
  LgnVec3 target = lgn_vec3(float(b.center.x()), float(b.center.y()), float(b.center.z()));
  LgnVec3 eye = lgn_vec3(float(b.center.x() + dist * std::sin(yaw * k)), float(b.center.y()),
                         float(b.center.z() + dist * std::cos(yaw * k)));
  return camera_look_at(eye, target, lgn_vec3(0, 1, 0), 65.0f, 1080, 1920);
}

TEST(SubjectFraming, AHeadOverflowingEveryFrameGetsAdvice) {
  std::vector<Camera> close;
  for (double yaw = -40; yaw <= 40; yaw += 10) close.push_back(phone(0.18, yaw));  // 18 cm: a close selfie
  FramingReport r = check_head_framing(head(), close);
  EXPECT_EQ(r.frames, 9u);
  EXPECT_EQ(r.touching, 9u);
  EXPECT_TRUE(r.every_frame());
  EXPECT_NE(r.advice().find("all 9 frames"), std::string::npos) << r.advice();
  EXPECT_NE(r.advice().find("arm's length"), std::string::npos) << r.advice();
}

TEST(SubjectFraming, ArmsLengthOrSomeGoodFramesPass) {
  std::vector<Camera> far;
  for (double yaw = -40; yaw <= 40; yaw += 10) far.push_back(phone(0.6, yaw));
  FramingReport r = check_head_framing(head(), far);
  EXPECT_EQ(r.touching, 0u);
  EXPECT_EQ(r.advice(), "");
  // A close pass plus a few frames from arm's length: the room was seen beside the head.
  std::vector<Camera> mixed = {phone(0.18, 0), phone(0.18, 20), phone(0.6, -20)};
  r = check_head_framing(head(), mixed);
  EXPECT_EQ(r.touching, 2u);
  EXPECT_FALSE(r.every_frame());
  EXPECT_EQ(r.advice(), "");
  // A camera inside the head's extent counts as touching (nothing around the head can be seen).
  EXPECT_EQ(check_head_framing(head(), {phone(0.05, 0)}).touching, 1u);
}

// Hair declared beyond the standard (train --hair 150: a taller, longer and wider box) is not the
// head: a capture that frames the head well passes with it as without, and one that overflows the
// frames overflows them as it does without.
TEST(SubjectFraming, DeclaredHairIsNotTheHead) {
  fit::HeadFrame f;  // facing +z, 1 unit = 1 m
  f.d_fwd = Eigen::Vector3d::UnitZ(), f.d_up = Eigen::Vector3d::UnitY();
  f.d_eye = f.d_up.cross(f.d_fwd);
  f.mm_per_unit = 1000.0;
  const Eigen::Vector3d eyes = head().center;
  fit::HeadExtents tall;
  tall.hair_mm = 150.0;
  const fit::HeadBox standard = fit::head_box_from_frame(f, eyes, {});
  const fit::HeadBox hair = fit::head_box_from_frame(f, eyes, tall);
  std::vector<Camera> near;  // 36 cm: the head fills the frame, with room beside it
  for (double yaw = -40; yaw <= 40; yaw += 10) near.push_back(phone(0.36, yaw));
  EXPECT_EQ(check_head_framing(standard, near).touching, 0u);
  EXPECT_EQ(check_head_framing(hair, near).touching, 0u);
  // Its box as the head (what the check used before) overflows 6 of those 9 frames.
  fit::HeadBox grown = hair;
  grown.extents = fit::HeadExtents{};
  EXPECT_GE(check_head_framing(grown, near).touching, 6u);
  std::vector<Camera> close;
  for (double yaw = -40; yaw <= 40; yaw += 10) close.push_back(phone(0.18, yaw));
  EXPECT_GE(check_head_framing(hair, close).touching, 8u);  // 18 cm: 8 of 9 overflow, as without hair
  EXPECT_EQ(check_head_framing(hair, close).touching, check_head_framing(standard, close).touching);
}

TEST(SubjectFraming, TheModelKeepsTheProblemSoNoFitPassesItAsGood) {
  nerf::Snapshot s;
  s.config.levels = 1;
  s.config.features_per_level = 1;
  s.config.log2_table_size = 8;
  s.config.base_resolution = s.config.finest_resolution = 2;
  s.config.density_hidden = s.config.geo_features = s.config.color_hidden = 1;
  s.config.color_hidden_layers = s.config.sh_degree = 1;
  s.step = 0.01f;
  s.params.assign(s.config.param_count(), 0.0f);
  s.occ = nerf::full_occupancy(2);
  s.metadata.subject_problem = check_head_framing(head(), {phone(0.18, 0)}).advice();
  ASSERT_FALSE(s.metadata.subject_problem.empty());
  nerf::Snapshot back = nerf::parse_snapshot(nerf::encode_snapshot(s), "m.lnerf");
  EXPECT_EQ(back.metadata.subject_problem, s.metadata.subject_problem);
}

}  // namespace
}  // namespace lorgnette::capture
