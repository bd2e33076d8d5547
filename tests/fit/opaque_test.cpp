// Haze is not a head (fit/opaque.h), on the temple spread's analytic head (temple_fit_test.cpp): a
// ball of radius 66 mm, centre 90 mm behind the hinges (70 mm to either side), clear of the rigid
// temples, wrapped in a haze shell out to 95 mm. The haze is denser than the probe's solid threshold
// everywhere, so counted point by point the head is 190 mm wide and the temples must spread past what
// a worn frame bends (closed form, temple_fit_test.cpp: 18.1 deg). Seen from outside, a semi-
// transparent shell (0.028 per mm: the 20 mm the rule sums outside a temple hide 43 %) never reaches
// 0.5 opacity in front of a temple: not head, and the temples stay straight. An opaque shell of the
// same size (1 per mm) is what a render shows as a head 190 mm wide: it still fails.
#include "fit/opaque.h"

#include <gtest/gtest.h>

#include <cmath>

#include "fit/input_checks.h"
#include "fit/temple_fit.h"

namespace lorgnette::fit {
namespace {

constexpr double kHx = 70.0, kLength = 120.0, kBall = 66.0, kShell = 95.0;
const Eigen::Vector3d kCentre{0, 0, -90};

DensityFn head_in_haze(float haze) {
  return [haze](const std::vector<Eigen::Vector3f>& p) {
    std::vector<float> s(p.size());
    for (size_t i = 0; i < p.size(); ++i) {
      const double d = (p[i].cast<double>() - kCentre).norm();
      s[i] = d < kBall ? 100.0f : d < kShell ? haze : 0.0f;
    }
    return s;
  };
}

HeadProbe probe(float haze) {
  std::vector<Eigen::Vector3d> pts;
  for (double t = 0.0; t <= kLength; t += 0.25)
    for (double s : {1.0, -1.0}) pts.emplace_back(s * kHx, 0.0, -t);
  ContactOptions c;
  c.density_threshold = 0.02f;  // the haze (0.028) is "solid" point by point
  return HeadProbe{head_in_haze(haze), kCentre, Eigen::Vector3d::UnitY(), 1.0, c, pts};
}

double spread_deg(const HeadProbe& head) {
  TempleFitInputs in;
  in.hinge_l = {kHx, 0, 0};
  in.hinge_r = {-kHx, 0, 0};
  const TempleFitResult t = fit_temples(in, head, 0.5, TempleFitOptions{});
  EXPECT_NEAR(t.left.spread_deg, t.right.spread_deg, 1e-9);
  return check_temple_spread(t).passed ? t.left.spread_deg : -t.left.spread_deg;
}

TEST(Opaque, SemiTransparentHazeIsNotAHead) {
  HeadProbe hazy = probe(0.028f);
  // Point by point: the closed form's 18.1 deg (atan2(90, 70) - acos(94.5 / hypot(70, 90))), failed.
  const double needed =
      (std::atan2(90.0, kHx) - std::acos((kShell - 0.5) / std::hypot(kHx, 90.0))) * 180.0 / M_PI;
  EXPECT_NEAR(-spread_deg(hazy), needed + 0.125, 0.135);
  // Behind 0.5 opacity only: the ball alone, which the rigid temples clear.
  hazy.density = density_behind_opacity(hazy, hazy.density);
  EXPECT_EQ(spread_deg(hazy), 0.0);
}

TEST(Opaque, AnOpaqueShellIsStillAHeadTooWideForTheFrame) {
  HeadProbe solid = probe(1.0f);
  solid.density = density_behind_opacity(solid, solid.density);
  EXPECT_LT(spread_deg(solid), -kMaxWornSpreadDeg);  // not passed, beyond the worn limit
}

TEST(Opaque, TheSkinLiesWhereItsOpacityReachesAHalf) {
  // Along a line out of the ball: points under 0.5 opacity of skin (100 per mm: 0.007 mm) and the
  // haze outside are solid; in the open haze, only where 0.5 opacity of haze lies outside them.
  HeadProbe h = probe(0.028f);
  const DensityFn f = density_behind_opacity(h, h.density);
  std::vector<Eigen::Vector3f> pts;
  for (double d : {60.0, 65.0, 70.0, 80.0, 91.0, 100.0})
    pts.push_back((kCentre + Eigen::Vector3d(d, 0, 0)).cast<float>());
  const std::vector<float> s = f(pts);
  EXPECT_GT(s[0], 1.0f);  // inside the ball
  EXPECT_GT(s[1], 1.0f);  // 1 mm under its surface: the ball's own opacity lies outside it
  EXPECT_EQ(s[2], 0.0f);  // in the haze: 20 mm of it summed outside, 43 %
  EXPECT_EQ(s[3], 0.0f);
  EXPECT_EQ(s[4], 0.0f);
  EXPECT_EQ(s[5], 0.0f);  // outside everything
}

}  // namespace
}  // namespace lorgnette::fit
