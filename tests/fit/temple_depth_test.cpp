// The temples at one depth (fit/temple_depth.h) on an exact scene: a head frame with d_fwd = +z and
// 1 mm per unit, a head that is an upright elliptic column (semi-axes 75 mm across, 110 mm deep,
// centred at z = -100 mm; opaque inside) whose widest points, the true temples, are (+-75, 0, -100)
// mm, seen by five cameras 500 mm away at yaw -20..20 deg whose detections are the true temples'
// exact projections. A "cast" temple is put 12 mm further along one view's ray (what a soft NeRF side
// does to the opacity depth) or 15 mm nearer the camera (what haze along a grazing ray does): either
// way it leaves the skin that a probe from the side meets, by 1-5 mm, while the true temple lies on
// it. The rule must bring the wrong temple onto its true point (every ray passes through it, so the
// median of the rays' points at the other temple's depth is the true point, to the float cameras'
// 1e-4 mm) and leave the right one where it is, whichever of the two lies in front; and must leave
// temples alone whose depths differ by less than the tolerance, or when it is disabled.
#include "fit/temple_depth.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "fit/camera_math.h"
#include "fit/fit.h"
#include "fit/landmark_ids.h"

namespace lorgnette::fit {
namespace {

const Eigen::Vector3d kLeft(75.0, 0.0, -100.0), kRight(-75.0, 0.0, -100.0);

// The elliptic column's density: a step to 1e4 per mm at its surface (a mesh-like skin).
class ColumnHead : public ViewSource {
 public:
  Image render(const Camera& c) override { return Image(int(c.width), int(c.height), 3, 1.0f); }
  std::vector<float> density(const std::vector<Eigen::Vector3f>& p) override {
    std::vector<float> d;
    for (const auto& q : p) {
      const double x = q.x() / 75.0, z = (q.z() + 100.0) / 110.0;
      d.push_back(x * x + z * z < 1.0 ? 1e4f : 0.0f);
    }
    return d;
  }
  Bounds bounds() const override { return {{-200, -200, -300}, {200, 200, 100}}; }
};

struct Scene {
  std::vector<ViewRecord> views;
  std::vector<TriangulatedPoint> points = std::vector<TriangulatedPoint>(lm::kCount);
  HeadFrame head;
  ColumnHead source;

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
  // Moves temple k `mm` along view v's ray through it: > 0 behind the true point, < 0 towards the camera.
  void push_along_ray(int k, size_t v, double mm) {
    const Ray r = camera_ray(views[v].camera, views[v].detection.points[k]);
    points[k].position += mm * r.dir;
  }
  TempleDepthResult balance(const TempleDepthOptions& o = {}) {
    return balance_temple_depths(source, views, head, o, points);
  }
};

TEST(TempleDepth, OffSkinIsTheGapToTheSideMetSquareOn) {
  Scene s;
  // The column's side at y = 0, z = -100 is x = +-75; the probe's opacity 0.5 lies ln 2 / 1e4 mm
  // inside a step of 1e4 per mm, and the march resolves it to well under 0.01 mm.
  EXPECT_NEAR(off_skin_mm(s.source, s.head, kLeft, +1, 30.0), 0.0, 0.01);
  EXPECT_NEAR(off_skin_mm(s.source, s.head, kRight + Eigen::Vector3d(-3, 0, 0), -1, 30.0), 3.0, 0.01);
  EXPECT_NEAR(off_skin_mm(s.source, s.head, kLeft + Eigen::Vector3d(-2, 0, 0), +1, 30.0), 2.0, 0.01);
  EXPECT_EQ(off_skin_mm(s.source, s.head, Eigen::Vector3d(200, 0, 0), +1, 30.0),
            std::numeric_limits<double>::infinity());
}

TEST(TempleDepth, MovesTheTempleBehindToTheOthersDepthAlongItsRays) {
  Scene s;
  s.push_along_ray(lm::kTempleL, 0, 12.0);
  EXPECT_GT((s.points[lm::kTempleL].position - kLeft).norm(), 11.0);
  TempleDepthResult r = s.balance();
  EXPECT_EQ(r.moved, +1);
  EXPECT_EQ(r.rays, 5);
  EXPECT_LT(r.gap_mm, -5.0);
  EXPECT_GT(r.off_skin_l_mm, 1.0);
  EXPECT_LT(r.off_skin_r_mm, 0.01);
  EXPECT_LT((s.points[lm::kTempleL].position - kLeft).norm(), 1e-4);    // float cameras
  EXPECT_LT((s.points[lm::kTempleR].position - kRight).norm(), 1e-12);  // the reference stays
  EXPECT_NE(r.summary().find("left temple"), std::string::npos) << r.summary();
  EXPECT_NE(r.summary().find("moved forward"), std::string::npos) << r.summary();
}

// The case the rule "the temple behind moves to the one in front" got wrong: the temple in front is
// the bad cast (haze along a grazing ray), and the right one, correct, was carried forward to it.
TEST(TempleDepth, MovesATempleCastInFrontBackToTheOthersDepth) {
  Scene s;
  s.push_along_ray(lm::kTempleL, 2, -15.0);  // the frontal view's ray, 15 mm towards the camera
  TempleDepthResult r = s.balance();
  EXPECT_GT(r.gap_mm, 5.0);  // the left lies in front
  EXPECT_EQ(r.moved, +1);
  EXPECT_GT(r.off_skin_l_mm, 1.0);
  EXPECT_LT((s.points[lm::kTempleL].position - kLeft).norm(), 1e-4);
  EXPECT_LT((s.points[lm::kTempleR].position - kRight).norm(), 1e-12);
  EXPECT_NE(r.summary().find("moved back"), std::string::npos) << r.summary();
}

TEST(TempleDepth, MovesTheRightTempleWhenItIsTheBadCast) {
  for (double mm : {9.0, -15.0}) {
    Scene s;
    s.push_along_ray(lm::kTempleR, 4, mm);
    TempleDepthResult r = s.balance();
    EXPECT_EQ(r.moved, -1) << mm;
    EXPECT_GT(std::abs(r.gap_mm), 5.0) << mm;
    EXPECT_LT((s.points[lm::kTempleR].position - kRight).norm(), 1e-4) << mm;
    EXPECT_LT((s.points[lm::kTempleL].position - kLeft).norm(), 1e-12) << mm;
  }
}

TEST(TempleDepth, KeepsTemplesWithinTheToleranceOrWhenDisabled) {
  Scene s;
  s.push_along_ray(lm::kTempleL, 2, 4.0);  // 4 mm behind: within the 5 mm tolerance
  const Eigen::Vector3d cast = s.points[lm::kTempleL].position;
  TempleDepthResult r = s.balance();
  EXPECT_EQ(r.moved, 0);
  const double behind = -(s.points[lm::kTempleL].position - kLeft).z();  // 4 mm along a ray 8.5 deg off z
  EXPECT_NEAR(r.gap_mm, -behind, 1e-9);
  EXPECT_GT(behind, 3.9);
  EXPECT_EQ(s.points[lm::kTempleL].position, cast);

  Scene t;
  t.push_along_ray(lm::kTempleL, 0, 12.0);
  const Eigen::Vector3d far = t.points[lm::kTempleL].position;
  TempleDepthOptions off;
  off.enabled = false;
  EXPECT_EQ(t.balance(off).moved, 0);
  EXPECT_EQ(t.points[lm::kTempleL].position, far);
}

TEST(TempleDepth, LeavesATempleWithoutUsableRaysWhereItIs) {
  Scene s;
  s.push_along_ray(lm::kTempleL, 0, 12.0);
  const Eigen::Vector3d cast = s.points[lm::kTempleL].position;
  for (auto& v : s.views) v.detection.found = false;
  EXPECT_EQ(s.balance().moved, 0);
  EXPECT_EQ(s.points[lm::kTempleL].position, cast);
}

// Both casts off in the same way (no side better supported, e.g. no skin at all within the probe):
// nothing tells which is right, so neither moves.
TEST(TempleDepth, KeepsBothWhenNeitherIsBetterSupported) {
  Scene s;
  s.push_along_ray(lm::kTempleL, 0, 12.0);
  s.points[lm::kTempleL].position.x() += 100.0, s.points[lm::kTempleR].position.x() -= 100.0;
  const Eigen::Vector3d l = s.points[lm::kTempleL].position, rr = s.points[lm::kTempleR].position;
  TempleDepthResult r = s.balance();
  EXPECT_EQ(r.moved, 0);
  EXPECT_EQ(r.off_skin_l_mm, std::numeric_limits<double>::infinity());
  EXPECT_EQ(s.points[lm::kTempleL].position, l);
  EXPECT_EQ(s.points[lm::kTempleR].position, rr);
}

}  // namespace
}  // namespace lorgnette::fit
