// Tests of the sphere-cap camera rig: cameras look at the target from the requested distance and
// angles, the rig covers the (yaw, pitch) box deterministically, and bad ranges are refused.
#include "synth/camera_rig.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lorgnette::synth {
namespace {

TEST(CameraRig, CamerasLookAtTheTargetFromTheRequestedAngles) {
  RigOptions rig;
  rig.views = 40;
  rig.seed = 3;
  rig.target = Eigen::Vector3f(0.1f, -0.2f, 0.05f);
  auto views = make_camera_rig(rig);
  ASSERT_EQ(views.size(), 40u);
  for (const auto& v : views) {
    EXPECT_GE(v.yaw_deg, rig.yaw_min_deg);
    EXPECT_LE(v.yaw_deg, rig.yaw_max_deg);
    EXPECT_GE(v.pitch_deg, rig.pitch_min_deg);
    EXPECT_LE(v.pitch_deg, rig.pitch_max_deg);
    // The target projects to the principal point (1e-3 px: float round-off at distance 3).
    float u, w;
    float depth = camera_project(&v.camera, lgn_vec3(rig.target.x(), rig.target.y(), rig.target.z()), &u, &w);
    EXPECT_NEAR(depth, rig.distance, 1e-4);
    EXPECT_NEAR(u, v.camera.cx, 1e-3);
    EXPECT_NEAR(w, v.camera.cy, 1e-3);
    // Camera up vector has no roll: its x axis is horizontal.
    EXPECT_NEAR(v.camera.c2w[4], 0.0f, 1e-6);
  }
  // Same seed, same rig; another seed, other angles.
  auto again = make_camera_rig(rig);
  EXPECT_EQ(again[5].yaw_deg, views[5].yaw_deg);
  rig.seed = 4;
  EXPECT_NE(make_camera_rig(rig)[5].yaw_deg, views[5].yaw_deg);
}

TEST(CameraRig, PositiveYawMovesTheCameraTowardsPlusX) {
  RigOptions rig;
  EXPECT_GT(rig_position(rig, 30.0f, 0.0f).x(), 0.0f);
  EXPECT_GT(rig_position(rig, 0.0f, 20.0f).y(), 0.0f);
  EXPECT_NEAR(rig_position(rig, 0.0f, 0.0f).z(), rig.distance, 1e-6);
}

TEST(CameraRig, FrameRadiusFitsTheView) {
  RigOptions rig;
  Camera c = rig_camera(rig, 0.0f, 0.0f);
  // A point frame_radius above the target stays inside the image (with the 5 % margin).
  float u, v;
  camera_project(&c, lgn_vec3(0, rig.frame_radius, 0), &u, &v);
  EXPECT_GT(v, 0.0f);
  EXPECT_LT(v, 0.05f * c.height);
}

TEST(CameraRig, RefusesBadRanges) {
  RigOptions rig;
  rig.yaw_min_deg = 10, rig.yaw_max_deg = -10;
  EXPECT_THROW(make_camera_rig(rig), std::runtime_error);
  rig = RigOptions{};
  rig.views = 0;
  EXPECT_THROW(make_camera_rig(rig), std::runtime_error);
  rig = RigOptions{};
  rig.width = 4;
  EXPECT_THROW(make_camera_rig(rig), std::runtime_error);
  rig = RigOptions{};
  rig.frame_radius = 5.0f;
  EXPECT_THROW(make_camera_rig(rig), std::runtime_error);
}

}  // namespace
}  // namespace lorgnette::synth
