// Surface depths along rays (fit/ray_surface.h) and the near-side rule for jaw-contour casts
// (fit/surface_landmarks.h), on analytic densities with closed-form answers.
#include "fit/ray_surface.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "fit/camera_math.h"
#include "fit/detect_views.h"
#include "fit/fit.h"
#include "fit/landmark_ids.h"
#include "fit/surface_landmarks.h"

namespace lorgnette::fit {
namespace {

// Density as a function of the point: no rendering.
class FieldSource : public ViewSource {
 public:
  explicit FieldSource(std::function<float(const Eigen::Vector3f&)> f) : f_(std::move(f)) {}
  Image render(const Camera& c) override { return Image(int(c.width), int(c.height), 3, 1.0f); }
  std::vector<float> density(const std::vector<Eigen::Vector3f>& p) override {
    std::vector<float> d;
    for (const auto& q : p) d.push_back(f_(q));
    return d;
  }
  Bounds bounds() const override { return {}; }

 private:
  std::function<float(const Eigen::Vector3f&)> f_;
};

const Eigen::Vector3d kOrigin(0, 0, 0), kDir(0, 0, 1);
// The ranges below are 2 units long: 512 coarse samples (3.9e-3 apart), 64 fine ones (6.2e-5 apart).
constexpr double kFineStep = 2.0 / 511 / 63;

TEST(OpacityDepth, ConstantSlabReachesHalfOpacityAtLn2OverSigma) {
  const float sigma = 50.0f;  // per unit, from z = 1
  FieldSource s([&](const Eigen::Vector3f& p) { return p.z() >= 1.0f ? sigma : 0.0f; });
  double t = 0.0;
  ASSERT_TRUE(opacity_depth(s, kOrigin, kDir, 0.0, 2.0, 0.5, &t));
  // Exact: 1 + ln 2 / 50 = 1.013863. The jump at z = 1 is resolved to one fine step.
  EXPECT_NEAR(t, 1.0 + std::log(2.0) / sigma, kFineStep);
  ASSERT_TRUE(opacity_depth(s, kOrigin, kDir, 0.0, 2.0, 0.9, &t));
  EXPECT_NEAR(t, 1.0 + std::log(10.0) / sigma, kFineStep);
}

TEST(OpacityDepth, LinearRampIsExactToRounding) {
  // density k (z - z0) above z0: optical depth k (t - z0)^2 / 2, which the trapezoid rule integrates
  // exactly when z0 is a coarse sample (a kink between samples would cost k dt^2 / 8 of optical
  // depth); the level is reached at z0 + sqrt(2 ln 2 / k). What remains is the linear interpolation
  // inside the fine step (k step^2 / 8 of optical depth, 4e-8 here) and float positions (1e-7).
  const double k = 400.0, z0 = 2.0 * 255 / 511;
  FieldSource s([&](const Eigen::Vector3f& p) { return p.z() > z0 ? float(k * (p.z() - z0)) : 0.0f; });
  double t = 0.0;
  ASSERT_TRUE(opacity_depth(s, kOrigin, kDir, 0.0, 2.0, 0.5, &t));
  EXPECT_NEAR(t, z0 + std::sqrt(2.0 * std::log(2.0) / k), 1e-6);
}

TEST(OpacityDepth, SeesThroughAFaintShellThatStopsTheFirstCrossing) {
  // A NeRF's haze: a 0.02-unit shell of density 10 (opacity 0.18) at z = 0.9, the skin at z = 1.
  FieldSource s([](const Eigen::Vector3f& p) {
    if (p.z() >= 0.9f && p.z() < 0.92f) return 10.0f;
    return p.z() >= 1.0f ? 1e4f : 0.0f;
  });
  double first = 0.0, opaque = 0.0;
  ASSERT_TRUE(first_surface_hit(s, kOrigin, kDir, 0.0, 2.0, 5.0f, &first));
  ASSERT_TRUE(opacity_depth(s, kOrigin, kDir, 0.0, 2.0, 0.5, &opaque));
  EXPECT_NEAR(first, 0.9, 2.0 / 511);
  EXPECT_NEAR(opaque, 1.0, 2 * kFineStep);  // the skin, as a mesh's first hit
}

TEST(OpacityDepth, ClearRayAndBadLevel) {
  FieldSource s([](const Eigen::Vector3f&) { return 0.1f; });  // optical depth 0.2 over the range
  double t = -1.0;
  EXPECT_FALSE(opacity_depth(s, kOrigin, kDir, 0.0, 2.0, 0.5, &t));
  EXPECT_TRUE(opacity_depth(s, kOrigin, kDir, 0.0, 2.0, 0.1, &t));  // 1 - e^{-0.1 t} = 0.1 at t = 1.0536
  EXPECT_NEAR(t, -std::log(0.9) / 0.1, 1e-6);
  EXPECT_THROW(opacity_depth(s, kOrigin, kDir, 0.0, 2.0, 1.0, &t), std::invalid_argument);
  EXPECT_THROW(opacity_depth(s, kOrigin, kDir, 0.0, 2.0, 0.0, &t), std::invalid_argument);
}

// A detection whose image half-widths (nose tip to each end of the jaw contour) are given.
FaceDetection face(double right_half_px, double left_half_px) {
  FaceDetection d;
  d.found = true;
  d.points.assign(lm::kCount, Eigen::Vector2d(100, 100));
  d.points[lm::kTempleR].x() = 100 - right_half_px;  // the subject's right is on the image left
  d.points[lm::kTempleL].x() = 100 + left_half_px;
  return d;
}

TEST(ContourSide, EachSideFromTheViewsThatTurnItTowardsTheCamera) {
  FaceDetection right_turned = face(60, 40), left_turned = face(40, 60), frontal = face(50, 49);
  for (int k : {lm::kTempleR, 3, 7}) {
    EXPECT_TRUE(contour_side_visible(k, right_turned, 0.025));
    EXPECT_FALSE(contour_side_visible(k, left_turned, 0.025));
    EXPECT_TRUE(contour_side_visible(k, frontal, 0.025));  // asymmetry -0.01: within the tolerance
  }
  for (int k : {9, 13, lm::kTempleL}) {
    EXPECT_FALSE(contour_side_visible(k, right_turned, 0.025));
    EXPECT_TRUE(contour_side_visible(k, left_turned, 0.025));
    EXPECT_TRUE(contour_side_visible(k, frontal, 0.025));
  }
  EXPECT_FALSE(contour_side_visible(lm::kTempleR, face(50, 55), 0.025));  // asymmetry -0.048
  EXPECT_TRUE(contour_side_visible(8, left_turned, 0.0));                 // the chin: any view
  EXPECT_TRUE(contour_side_visible(lm::kNoseTip, left_turned, 0.0));      // not on the contour
}

TEST(ContourSide, CastUsesOnlyTheNearSideViews) {
  // A unit ball at the origin; two views see landmark 0 at pixels whose rays meet the ball at known
  // points. The view that turns the right side away puts its point on a grazing ray; only the other
  // one may count.
  FieldSource ball([](const Eigen::Vector3f& p) { return p.norm() < 1.0f ? 1e4f : 0.0f; });
  Orbit orbit;
  orbit.distance = 5.0;
  auto view = [&](const Eigen::Vector3d& eye, const Eigen::Vector3d& aim, double right, double left) {
    ViewRecord v;
    v.camera = look_at_camera(eye, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), 30.0, 200, 200);
    v.detection = face(right, left);
    Eigen::Vector2d uv;
    EXPECT_TRUE(camera_project(v.camera, aim, &uv));
    v.detection.points[lm::kTempleR] = uv;  // the landmark's pixel: the ray through `aim`
    return v;
  };
  const Eigen::Vector3d near_hit = Eigen::Vector3d(-0.6, 0.0, 0.8),
                        grazing = Eigen::Vector3d(-1.0, 0.0, -0.3);
  std::vector<ViewRecord> views = {view({-1.0, 0.0, 5.0}, near_hit, 60, 40),
                                   view({3.0, 0.0, 4.0}, grazing, 40, 60)};
  std::vector<TriangulatedPoint> pts(lm::kCount);
  SurfaceCastOptions so;
  so.first = so.last = lm::kTempleR;
  so.max_yaw_deg = 90.0;
  cast_surface_landmarks(ball, views, orbit, so, 10.0f, pts);
  ASSERT_TRUE(pts[lm::kTempleR].ok);
  ASSERT_EQ(pts[lm::kTempleR].inliers, std::vector<int>{0});
  // The ball's surface along the first view's ray; the mesh-like step is resolved to a fine step.
  EXPECT_LT((pts[lm::kTempleR].position - near_hit).norm(), 1e-3);
}

// snap_to_surface on a quarter space (solid where x <= 0 and z <= 0: a front at z = 0 and a steep side
// at x = 0) seen by three views 30 deg apart. With `nearest`, a landmark just inside the side goes to
// the nearest skin, square to the mean ray; along the mean ray alone (the default) it goes to the
// front. One just behind the flat front goes straight forward either way. The searches span 0.2
// units: 512 coarse samples, then 64 fine ones (6e-6 apart).
TEST(SnapToSurface, NearestTakesEachPointToItsNearestSkin) {
  FieldSource s([](const Eigen::Vector3f& p) { return p.x() <= 0.0f && p.z() <= 0.0f ? 100.0f : 0.0f; });
  std::vector<ViewRecord> views(3);
  const double yaw[3] = {-0.5236, 0.0, 0.5236};  // -30, 0, +30 deg
  for (int i = 0; i < 3; ++i)
    views[i].camera = look_at_camera(3.0 * Eigen::Vector3d(std::sin(yaw[i]), 0.0, std::cos(yaw[i])),
                                     Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), 30.0, 64, 64);
  std::vector<TriangulatedPoint> start(2);
  start[0].position = {-0.03, 0.0, -0.05};  // 0.03 inside the side, 0.05 behind the front
  start[1].position = {-0.5, 0.0, -0.02};   // 0.02 behind the front, far from the side
  for (TriangulatedPoint& p : start) p.ok = true, p.inliers = {0, 1, 2};
  std::vector<TriangulatedPoint> nearest = start, along = start;
  ASSERT_EQ(snap_to_surface(s, views, 0.1, 1.0f, nearest, -1, -1, 0.0, true), 2);
  ASSERT_EQ(snap_to_surface(s, views, 0.1, 1.0f, along, -1, -1), 2);
  EXPECT_NEAR(nearest[0].position.x(), 0.0, 1e-5);
  EXPECT_NEAR(nearest[0].position.y(), 0.0, 1e-9);
  EXPECT_NEAR(nearest[0].position.z(), -0.05, 1e-9);
  EXPECT_NEAR(nearest[0].sigma, 0.03, 1e-5);  // the move is added to the point's uncertainty
  EXPECT_NEAR(along[0].position.x(), -0.03, 1e-9);
  EXPECT_NEAR(along[0].position.z(), 0.0, 1e-5);
  EXPECT_NEAR(along[0].sigma, 0.05, 1e-5);
  for (const auto* p : {&nearest[1], &along[1]}) {
    EXPECT_NEAR(p->position.x(), -0.5, 1e-9);
    EXPECT_NEAR(p->position.z(), 0.0, 1e-5);
  }
}

}  // namespace
}  // namespace lorgnette::fit
