// The cap of views stays within its yaw/pitch range, contains the frontal view, and its cameras look
// at the orbit's target from the requested distance.
#include "fit/view_planning.h"

#include <gtest/gtest.h>

#include "fit/camera_math.h"

namespace lorgnette::fit {
namespace {

TEST(ViewPlanning, CapCoversTheRange) {
  CapOptions c;
  c.views = 30;
  c.yaw_range_deg = 40;
  c.pitch_range_deg = 10;
  auto a = cap_angles(c);
  ASSERT_EQ(a.size(), 30u);
  EXPECT_EQ(a[0], Eigen::Vector2d(0, 0));
  double min_yaw = 0, max_yaw = 0;
  for (const auto& v : a) {
    EXPECT_LE(std::abs(v.x()), 40.0 + 1e-9);
    EXPECT_LE(std::abs(v.y()), 10.0 + 1e-9);
    min_yaw = std::min(min_yaw, v.x()), max_yaw = std::max(max_yaw, v.x());
  }
  EXPECT_LT(min_yaw, -30.0);  // the spiral reaches near both ends
  EXPECT_GT(max_yaw, 30.0);
  EXPECT_THROW(cap_angles(CapOptions{0, 30, 10}), std::runtime_error);
}

TEST(ViewPlanning, OrbitCamerasLookAtTheTarget) {
  Orbit o;
  o.target = {0.5, 1.0, -0.2};
  o.distance = 3.0;
  for (double yaw : {-40.0, 0.0, 25.0}) {
    Camera cam = orbit_camera(o, yaw, 10.0);
    Eigen::Vector2d uv;
    ASSERT_TRUE(camera_project(cam, o.target, &uv));
    EXPECT_NEAR(uv.x(), o.width / 2.0, 1e-3);
    EXPECT_NEAR(uv.y(), o.height / 2.0, 1e-3);
    EXPECT_NEAR((camera_center(cam) - o.target).norm(), 3.0, 1e-5);
  }
  // Yaw 0 sits on the front direction.
  EXPECT_LT((camera_center(orbit_camera(o, 0, 0)) - (o.target + 3.0 * o.front)).norm(), 1e-5);
}

}  // namespace
}  // namespace lorgnette::fit
