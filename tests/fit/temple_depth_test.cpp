// The temples at one depth (fit/temple_depth.h) on an exact scene: a head frame with d_fwd = +z and
// 1 mm per unit, true temples at (+-75, 0, -100) mm, seen by five cameras 500 mm away at yaw -20..20
// deg whose detections are the true temples' exact projections. The "cast" left temple is put 12 mm
// further along the first view's ray (what a soft NeRF side does to the opacity depth): the rule must
// bring it back onto the true point (every ray passes through it, so the median of the rays' points at
// the right temple's depth is the true point, to the float cameras' 1e-4 mm), and must leave temples alone
// whose depths differ by less than the tolerance, or when it is disabled; a right temple behind is moved
// alike.
#include "fit/temple_depth.h"

#include <gtest/gtest.h>

#include <cmath>

#include "fit/camera_math.h"
#include "fit/fit.h"
#include "fit/landmark_ids.h"

namespace lorgnette::fit {
namespace {

const Eigen::Vector3d kLeft(75.0, 0.0, -100.0), kRight(-75.0, 0.0, -100.0);

struct Scene {
  std::vector<ViewRecord> views;
  std::vector<TriangulatedPoint> points = std::vector<TriangulatedPoint>(lm::kCount);
  HeadFrame head;

  Scene() {
    head.d_fwd = Eigen::Vector3d::UnitZ(), head.d_up = Eigen::Vector3d::UnitY();
    head.d_eye = Eigen::Vector3d::UnitX(), head.mm_per_unit = 1.0;
    for (double yaw : {-20.0, -10.0, 0.0, 10.0, 20.0}) {
      const double a = yaw * M_PI / 180.0;
      ViewRecord v;
      v.camera = look_at_camera(500.0 * Eigen::Vector3d(std::sin(a), 0.0, std::cos(a)),
                                Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), 30.0, 512, 512);
      v.yaw_deg = yaw;
      v.detection.found = true;
      v.detection.points.assign(lm::kCount, Eigen::Vector2d::Zero());
      for (auto [k, p] : {std::pair{lm::kTempleL, kLeft}, std::pair{lm::kTempleR, kRight}})
        EXPECT_TRUE(camera_project(v.camera, p, &v.detection.points[k]));
      views.push_back(v);
    }
    for (auto [k, p] : {std::pair{lm::kTempleL, kLeft}, std::pair{lm::kTempleR, kRight}}) {
      points[k].position = p, points[k].ok = true;
      points[k].inliers = {0, 1, 2, 3, 4};
    }
  }
  // Moves temple k `mm` further along view v's ray through it (behind the true point).
  void push_back_along_ray(int k, size_t v, double mm) {
    const Ray r = camera_ray(views[v].camera, views[v].detection.points[k]);
    points[k].position += mm * r.dir;
  }
};

TEST(TempleDepth, MovesTheTempleBehindToTheOthersDepthAlongItsRays) {
  Scene s;
  s.push_back_along_ray(lm::kTempleL, 0, 12.0);
  const double before = (s.points[lm::kTempleL].position - kLeft).norm();
  EXPECT_GT(before, 11.0);
  TempleDepthResult r = balance_temple_depths(s.views, s.head, {}, s.points);
  EXPECT_EQ(r.moved, +1);
  EXPECT_EQ(r.rays, 5);
  EXPECT_LT(r.gap_mm, -5.0);
  EXPECT_LT((s.points[lm::kTempleL].position - kLeft).norm(), 1e-4);    // float cameras
  EXPECT_LT((s.points[lm::kTempleR].position - kRight).norm(), 1e-12);  // the reference stays
  EXPECT_NE(r.summary().find("left temple"), std::string::npos) << r.summary();
}

TEST(TempleDepth, MovesTheRightTempleWhenItIsTheOneBehind) {
  Scene s;
  s.push_back_along_ray(lm::kTempleR, 4, 9.0);
  TempleDepthResult r = balance_temple_depths(s.views, s.head, {}, s.points);
  EXPECT_EQ(r.moved, -1);
  EXPECT_GT(r.gap_mm, 5.0);
  EXPECT_LT((s.points[lm::kTempleR].position - kRight).norm(), 1e-4);
}

TEST(TempleDepth, KeepsTemplesWithinTheToleranceOrWhenDisabled) {
  Scene s;
  s.push_back_along_ray(lm::kTempleL, 2, 4.0);  // 4 mm behind: within the 5 mm tolerance
  const Eigen::Vector3d cast = s.points[lm::kTempleL].position;
  TempleDepthResult r = balance_temple_depths(s.views, s.head, {}, s.points);
  EXPECT_EQ(r.moved, 0);
  const double behind = -(s.points[lm::kTempleL].position - kLeft).z();  // 4 mm along a ray 8.5 deg off z
  EXPECT_NEAR(r.gap_mm, -behind, 1e-9);
  EXPECT_GT(behind, 3.9);
  EXPECT_EQ(s.points[lm::kTempleL].position, cast);

  Scene t;
  t.push_back_along_ray(lm::kTempleL, 0, 12.0);
  const Eigen::Vector3d far = t.points[lm::kTempleL].position;
  TempleDepthOptions off;
  off.enabled = false;
  EXPECT_EQ(balance_temple_depths(t.views, t.head, off, t.points).moved, 0);
  EXPECT_EQ(t.points[lm::kTempleL].position, far);
}

TEST(TempleDepth, LeavesATempleWithoutUsableRaysWhereItIs) {
  Scene s;
  s.push_back_along_ray(lm::kTempleL, 0, 12.0);
  const Eigen::Vector3d cast = s.points[lm::kTempleL].position;
  for (auto& v : s.views) v.detection.found = false;
  EXPECT_EQ(balance_temple_depths(s.views, s.head, {}, s.points).moved, 0);
  EXPECT_EQ(s.points[lm::kTempleL].position, cast);
}

}  // namespace
}  // namespace lorgnette::fit
