// The temple spread search (fit/temple_fit.h) on an analytic head: a ball of radius R whose centre
// lies behind the hinges. A temple is the straight segment from its hinge (x = +-hx, z = 0) back
// along -z; spread by theta it is the line through the hinge with direction (+-sin, 0, -cos), whose
// distance to the centre (hx, zc relative) is D cos(theta - phi0), D = hypot(hx, zc),
// phi0 = atan2(|zc|, hx). The samples lie in the ball's equatorial plane and the probe axis goes
// through the centre, so a sample's penetration is exactly R - |p - c|, and the temple clears the
// allowed depth L when D cos(theta - phi0) >= R - L:
//   theta* = phi0 - acos((R - L) / D)     (the perpendicular's foot lies far behind the ramp).
// The search must return the first grid angle at or above theta*; tolerance: one step (0.25 deg)
// plus 0.01 deg for the 0.25 mm sampling of the segment and float density queries (~1e-4 deg).
#include "fit/temple_fit.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lorgnette::fit {
namespace {

constexpr double kHx = 70.0, kLength = 120.0;

struct Ball {
  Eigen::Vector3d c;
  double r;
  DensityFn fn() const {
    return [c = c.cast<float>(), r = float(r)](const std::vector<Eigen::Vector3f>& p) {
      std::vector<float> s(p.size());
      for (size_t i = 0; i < p.size(); ++i) s[i] = (p[i] - c).norm() < r ? 100.0f : 0.0f;
      return s;
    };
  }
};

std::vector<Eigen::Vector3d> temples() {
  std::vector<Eigen::Vector3d> pts;
  for (double t = 0.0; t <= kLength; t += 0.25)
    for (double s : {1.0, -1.0}) pts.emplace_back(s * kHx, 0.0, -t);
  for (double x = -60; x <= 60; x += 1.0) pts.emplace_back(x, 0.0, 5.0);  // a front, ahead of the hinges
  return pts;
}

TempleFitResult run(const Ball& ball, double limit = 0.5, TempleFitOptions opt = {}) {
  TempleFitInputs in;
  in.hinge_l = {kHx, 0, 0};
  in.hinge_r = {-kHx, 0, 0};
  HeadProbe head{ball.fn(), ball.c, Eigen::Vector3d::UnitY(), 1.0, ContactOptions{}, temples()};
  return fit_temples(in, head, limit, opt);
}

// theta* for a temple whose hinge is hx from the centre sideways and |zc| ahead of it.
double needed_deg(double hx, double zc, double r, double limit) {
  return (std::atan2(std::abs(zc), hx) - std::acos((r - limit) / std::hypot(hx, zc))) * 180.0 / M_PI;
}

TEST(TempleFit, SpreadMatchesTheClosedForm) {
  for (double r : {75.0, 78.0}) {
    Ball ball{{0, 0, -90}, r};
    TempleFitResult res = run(ball);
    const double want = needed_deg(kHx, -90, r, 0.5);
    ASSERT_TRUE(res.fitted);
    for (const TempleSideFit* s : {&res.left, &res.right}) {
      EXPECT_GE(s->spread_deg, want - 0.01) << "R " << r;
      EXPECT_LE(s->spread_deg, want + 0.25 + 0.01) << "R " << r;
      EXPECT_NEAR(s->penetration_before_mm, r - kHx, 0.25);  // the walk's resolution
      EXPECT_LE(s->penetration_mm, 0.5);
      EXPECT_TRUE(s->clear);
      EXPECT_EQ(s->points, int(kLength / 0.25));  // the hinge sample itself is rigid
    }
    EXPECT_EQ(res.bend.left.spread_deg, res.left.spread_deg);
    EXPECT_EQ(res.bend.right.spread_deg, res.right.spread_deg);
    EXPECT_TRUE(temple_warnings(res).empty());
  }
}

TEST(TempleFit, EachSideOnItsOwn) {
  // The ball 3 mm to the wearer's left: the left temple needs more spread than the right.
  Ball ball{{3, 0, -90}, 76.0};
  TempleFitResult res = run(ball);
  EXPECT_NEAR(res.left.spread_deg, needed_deg(kHx - 3, -90, 76, 0.5) + 0.125, 0.135);
  EXPECT_NEAR(res.right.spread_deg, needed_deg(kHx + 3, -90, 76, 0.5) + 0.125, 0.135);
  EXPECT_GT(res.left.spread_deg, res.right.spread_deg + 1.0);
}

TEST(TempleFit, NothingToFixMeansNoSpread) {
  TempleFitResult res = run(Ball{{0, 0, -90}, 60.0});
  EXPECT_EQ(res.left.spread_deg, 0.0);
  EXPECT_EQ(res.right.spread_deg, 0.0);
  EXPECT_EQ(res.left.penetration_before_mm, 0.0);
  EXPECT_FALSE(res.bend.active());
}

TEST(TempleFit, TooNarrowAFrameFails) {
  // R = 110 needs ~36 deg, beyond the 25 deg maximum: both sides keep the maximum, still clipping.
  Ball ball{{0, 0, -90}, 110.0};
  ASSERT_GT(needed_deg(kHx, -90, 110, 0.5), 25.0);
  TempleFitResult res = run(ball);
  for (const TempleSideFit* s : {&res.left, &res.right}) {
    EXPECT_EQ(s->spread_deg, 25.0);
    EXPECT_FALSE(s->clear);
    EXPECT_GT(s->penetration_mm, 0.5);
    EXPECT_LT(s->penetration_mm, s->penetration_before_mm);
  }
  std::vector<std::string> w = temple_warnings(res);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_NE(w[0].find("left temple still passes"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("25.0 deg"), std::string::npos) << w[0];
}

TEST(TempleFit, BadOptionsAreClearErrors) {
  TempleFitOptions opt;
  opt.step_deg = 0.0;
  EXPECT_THROW(run(Ball{{0, 0, -90}, 75.0}, 0.5, opt), std::runtime_error);
}

}  // namespace
}  // namespace lorgnette::fit
