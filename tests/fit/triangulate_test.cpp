// Triangulation against exact synthetic observations (pinhole cameras looking at known points),
// with detector noise, and with gross outliers that the robust loop must reject.
#include "fit/triangulate.h"

#include <gtest/gtest.h>

#include <random>

#include "fit/camera_math.h"
#include "fit/view_planning.h"

namespace lorgnette::fit {
namespace {

std::vector<Camera> ring(int k) {
  Orbit o;
  o.distance = 4.0;
  CapOptions c;
  c.views = k;
  return cap_cameras(o, c);
}

std::vector<Observation> observe(const std::vector<Camera>& cams, const Eigen::Vector3d& p) {
  std::vector<Observation> obs;
  for (const auto& c : cams) {
    Eigen::Vector2d uv;
    EXPECT_TRUE(camera_project(c, p, &uv));
    obs.push_back({&c, uv});
  }
  return obs;
}

TEST(NearestPointToRays, ExactForIntersectingRays) {
  Eigen::Vector3d p(0.3, -0.2, 0.5);
  std::vector<Eigen::Vector3d> o{{1, 0, 0}, {0, 2, 0}, {0, 0, -3}}, d;
  for (const auto& oi : o) d.push_back((p - oi).normalized());
  EXPECT_LT((nearest_point_to_rays(o, d) - p).norm(), 1e-12);
}

TEST(NearestPointToRays, MidpointOfSkewRays) {
  // x axis at z = 0 and y axis at z = 2: the nearest point is (0, 0, 1).
  Eigen::Vector3d p = nearest_point_to_rays({{0, 0, 0}, {0, 0, 2}}, {{1, 0, 0}, {0, 1, 0}});
  EXPECT_LT((p - Eigen::Vector3d(0, 0, 1)).norm(), 1e-12);
}

TEST(NearestPointToRays, ParallelRaysThrow) {
  EXPECT_THROW(nearest_point_to_rays({{0, 0, 0}, {1, 0, 0}}, {{0, 0, 1}, {0, 0, 1}}), std::runtime_error);
}

TEST(Triangulate, ExactObservationsRecoverThePoint) {
  auto cams = ring(9);
  Eigen::Vector3d p(0.1, 0.2, -0.15);
  auto t = triangulate_point(observe(cams, p));
  ASSERT_TRUE(t.ok) << t.why;
  // float camera math (camera_types.h): ~1e-6 relative on a 4-unit baseline.
  EXPECT_LT((t.position - p).norm(), 1e-4);
  EXPECT_EQ(t.inliers.size(), 9u);
  EXPECT_LT(t.rms_reprojection_px, 0.01);
}

TEST(Triangulate, NoiseGivesErrorWithinItsSigma) {
  auto cams = ring(15);
  Eigen::Vector3d p(0.0, 0.1, 0.2);
  auto obs = observe(cams, p);
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);  // 1 px detector noise
  for (auto& o : obs) o.uv += Eigen::Vector2d(n(rng), n(rng));
  auto t = triangulate_point(obs);
  ASSERT_TRUE(t.ok) << t.why;
  // 1 px at f ~ 1150 px and 4 units ~ 3.5e-3 units per ray; 15 rays over +-35 deg: the error should
  // be within a few sigma, and sigma in the right range.
  EXPECT_LT((t.position - p).norm(), 4.0 * t.sigma + 1e-4);
  EXPECT_GT(t.sigma, 1e-4);
  EXPECT_LT(t.sigma, 2e-2);
  EXPECT_NEAR(t.rms_reprojection_px, 1.2, 0.8);
}

TEST(Triangulate, RejectsGrossOutliers) {
  auto cams = ring(12);
  Eigen::Vector3d p(-0.1, 0.0, 0.1);
  auto obs = observe(cams, p);
  obs[3].uv += Eigen::Vector2d(60, -20);  // a wrong detection in two views
  obs[7].uv += Eigen::Vector2d(-35, 40);
  auto t = triangulate_point(obs);
  ASSERT_TRUE(t.ok) << t.why;
  EXPECT_EQ(t.inliers.size(), 10u);
  EXPECT_LT((t.position - p).norm(), 1e-4);
  EXPECT_GT(t.reprojection_px[3], 30.0);
}

TEST(Triangulate, SingleViewOrNarrowBaselineIsNotOk) {
  auto cams = ring(1);
  auto t = triangulate_point(observe(cams, Eigen::Vector3d::Zero()));
  EXPECT_FALSE(t.ok);
  EXPECT_FALSE(t.why.empty());
  Orbit o;
  std::vector<Camera> pair{orbit_camera(o, 0, 0), orbit_camera(o, 0.5, 0)};  // 0.5 deg apart
  auto n = triangulate_point(observe(pair, Eigen::Vector3d::Zero()));
  EXPECT_FALSE(n.ok);
  EXPECT_NE(n.why.find("no depth"), std::string::npos);
}

}  // namespace
}  // namespace lorgnette::fit
