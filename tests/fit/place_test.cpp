// Kabsch (incl. the reflection case), the scale policies, Eq. 4-5 placement with a known answer and
// the contact refinement against an analytic head (a sphere of known radius).
#include "fit/place.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

namespace lorgnette::fit {
namespace {

Eigen::Matrix3d some_rotation() {
  return (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()) *
          Eigen::AngleAxisd(-0.3, Eigen::Vector3d::UnitY()))
      .toRotationMatrix();
}

TEST(Kabsch, RecoversARotationExactly) {
  Eigen::Matrix3d r = some_rotation();
  std::vector<Eigen::Vector3d> a{{1, 0, 0}, {0, 2, 0}, {0.5, -1, 3}, {-2, 1, 1}}, b;
  for (const auto& v : a) b.push_back(r * v);
  EXPECT_LT((kabsch(a, b) - r).norm(), 1e-12);
}

TEST(Kabsch, TwoVectorsAreEnough) {
  // Eq. 5 uses exactly two difference vectors: rank-2 covariance, unique proper rotation.
  Eigen::Matrix3d r = some_rotation();
  std::vector<Eigen::Vector3d> a{{-70, 0, -100}, {70, 0, -100}};
  std::vector<Eigen::Vector3d> b{r * a[0], r * a[1]};
  Eigen::Matrix3d k = kabsch(a, b);
  EXPECT_LT((k - r).norm(), 1e-12);
  EXPECT_NEAR(k.determinant(), 1.0, 1e-12);
}

TEST(Kabsch, ReflectionIsRefusedAndAProperRotationReturned) {
  // Targets are a mirror image of the sources: the unconstrained optimum has det -1.
  std::vector<Eigen::Vector3d> a{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  std::vector<Eigen::Vector3d> b{{-1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Eigen::Matrix3d k = kabsch(a, b);
  EXPECT_NEAR(k.determinant(), 1.0, 1e-12);
  EXPECT_LT((k * k.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  // The best proper rotation is a half turn about one of the kept axes: one vector still ends up
  // opposite its target, residual |2|^2 = 4.
  double res = 0;
  for (int i = 0; i < 3; ++i) res += (k * a[i] - b[i]).squaredNorm();
  EXPECT_NEAR(res, 4.0, 1e-9);
}

TEST(Kabsch, ParallelVectorsThrow) {
  EXPECT_THROW(kabsch({{1, 0, 0}, {2, 0, 0}}, {{0, 1, 0}, {0, 2, 0}}), std::runtime_error);
}

TEST(Kabsch, NoisyTargetsWithinTolerance) {
  Eigen::Matrix3d r = some_rotation();
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 0.5);  // 0.5 mm noise on 30-120 mm vectors
  std::vector<Eigen::Vector3d> a{{-70, 0, -100}, {70, 0, -100}, {0, 30, 5}}, b;
  for (const auto& v : a) b.push_back(r * v + Eigen::Vector3d(n(rng), n(rng), n(rng)));
  Eigen::AngleAxisd err(kabsch(a, b) * r.transpose());
  // 0.5 mm over lever arms >= 30 mm: at most ~1 deg (0.5/30 rad) on the worst axis.
  EXPECT_LT(err.angle() * 180.0 / M_PI, 1.0);
}

TEST(Place, PutsReferencePointsOnLandmarksExactly) {
  GlassesRefPoints g;  // g_c at origin, temple tips 140 mm apart
  Eigen::Matrix3d r = some_rotation();
  const double s = 0.02;  // scene units per mm
  Eigen::Vector3d t(0.3, -0.1, 2.0);
  PlaceInputs in;
  in.f_c = s * r * g.g_c + t;
  in.f_l = s * r * g.g_l + t;
  in.f_r = s * r * g.g_r + t;
  in.t_l = in.f_l, in.t_r = in.f_r;  // stretch scale = |t_l - t_r| / |g_l - g_r| = s
  in.mm_per_unit = 1.0 / s;
  for (ScalePolicy pol : {ScalePolicy::kStretch, ScalePolicy::kTrueSize}) {
    Placement p = place_glasses(g, in, pol);
    EXPECT_NEAR(p.scale, s, 1e-12);
    auto apply = [&](const Eigen::Vector3d& v) {
      return Eigen::Vector3d(p.transform.block<3, 3>(0, 0) * v + p.transform.block<3, 1>(0, 3));
    };
    EXPECT_LT((apply(g.g_c) - in.f_c).norm(), 1e-12);
    EXPECT_LT((apply(g.g_l) - in.f_l).norm(), 1e-12);
    EXPECT_LT((apply(g.g_r) - in.f_r).norm(), 1e-12);
  }
  EXPECT_EQ(parse_scale_policy("true-size"), ScalePolicy::kTrueSize);
  EXPECT_THROW(parse_scale_policy("big"), std::runtime_error);
}

// A sphere "head" of radius 80 mm at the origin (1 scene unit = 1 mm); the frame is a flat plate of
// points in front of it at canonical z = 0. The refinement must bring the plate to rest on the
// sphere: the centre point on the surface within one search step.
TEST(Contact, PlateRestsOnASphere) {
  const double radius = 80.0;
  DensityFn sphere = [&](const std::vector<Eigen::Vector3f>& pts) {
    std::vector<float> d;
    for (const auto& p : pts) d.push_back(p.norm() < radius ? 1000.0f : 0.0f);
    return d;
  };
  std::vector<Eigen::Vector3d> plate;
  for (int x = -20; x <= 20; x += 2)
    for (int y = -10; y <= 10; y += 2) plate.emplace_back(x, y, 0.0);
  ContactOptions opt;
  opt.step_mm = 0.25;
  for (double start : {90.0, 70.0}) {  // floating in front, then sunk into the sphere
    Placement p;
    p.transform.block<3, 1>(0, 3) = Eigen::Vector3d(0, 0, start);
    HeadProbe head{sphere, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), 1.0, opt, plate};
    ContactResult r = refine_contact(p, head, Eigen::Vector3d::UnitZ());
    double z = p.transform(2, 3);
    EXPECT_GE(z, radius - 1e-9) << "start " << start;
    EXPECT_LE(z, radius + opt.step_mm + 1e-9) << "start " << start;
    EXPECT_EQ(r.penetration_mm, 0.0);
    if (start < radius) {
      EXPECT_GT(r.penetration_before_mm, 9.0);  // sunk 10 mm at the centre
    }
  }
}

}  // namespace
}  // namespace lorgnette::fit
