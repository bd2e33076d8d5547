// The frame rides up a nose wider than its bridge (fit/nose_rest.h, refine_contact in fit/place.h),
// on an analytic face with ground truth. Scene = canonical millimetres (1 mm per unit), forward +z,
// up +y. The frame's front: a bridge bar over g_c (the
// origin, the bar's underside at its back face) and two rims whose inner edges leave an 18 mm gap,
// their lowest points 27 mm under g_c. The face: a plane 12 mm behind the bridge (eyes, cheeks) and a
// nose of width w(y) = w0 - k y, its front at the bridge's depth above g_c and jutting forward by
// 0.8 mm per mm below it. With an 18 mm gap the rims' lowest points clear the nose once they stand
// where it is 18 mm wide, y18 = (w0 - 18) / k: the frame rests on its bridge from a rise of 27 + y18,
// and below it the rims would need more than the contact's 15 mm slide (the nose juts 17 mm there).
#include "fit/nose_rest.h"

#include <gtest/gtest.h>

#include <cmath>

#include "fit/input_checks.h"
#include "fit/place.h"

namespace lorgnette::fit {
namespace {

constexpr double kGap = 18.0, kRimLow = -27.0, kEyesZ = -12.0, kJut = 0.8;

struct Nose {
  double w0 = 14.0, k = 4.0 / 21.25;  // 18 mm wide 21.25 mm under g_c: the rims rest from 5.75 mm up
  double y18() const { return (w0 - kGap) / k; }
  DensityFn fn() const {
    return [w0 = w0, k = k](const std::vector<Eigen::Vector3f>& p) {
      std::vector<float> s(p.size());
      for (size_t i = 0; i < p.size(); ++i) {
        const double x = p[i].x(), y = p[i].y(), z = p[i].z();
        const bool face = z < kEyesZ;
        const bool nose =
            y > -45.0 && y < 20.0 && std::abs(x) < 0.5 * (w0 - k * y) && z < kJut * std::max(0.0, -y);
        s[i] = face || nose ? 100.0f : 0.0f;
      }
      return s;
    };
  }
};

// The front's samples on a 0.5 mm grid: the bridge bar (|x| <= 10.5, 0 <= y <= 3) and the two rims'
// inner and lower bars (3 mm wide), all 4 mm deep from z = 0 (the back face) forwards.
std::vector<Eigen::Vector3d> front() {
  std::vector<Eigen::Vector3d> pts;
  auto box = [&](double x0, double x1, double y0, double y1) {
    for (double x = x0; x <= x1 + 1e-9; x += 0.5)
      for (double y = y0; y <= y1 + 1e-9; y += 0.5)
        for (double z = 0.0; z <= 4.0 + 1e-9; z += 1.0) pts.emplace_back(x, y, z);
  };
  box(-10.5, 10.5, 0.0, 3.0);
  for (double side : {1.0, -1.0}) {
    const double a = 0.5 * kGap, b = a + 3.0;
    side > 0 ? box(a, b, kRimLow, 3.0) : box(-b, -a, kRimLow, 3.0);
    side > 0 ? box(a, 60.0, kRimLow, kRimLow + 3.0) : box(-60.0, -a, kRimLow, kRimLow + 3.0);
  }
  return pts;
}

HeadProbe head(const Nose& nose, double max_rise_mm) {
  ContactOptions c;
  c.density_threshold = 1.0f;
  c.max_rise_mm = max_rise_mm;
  return HeadProbe{nose.fn(), {0.0, 0.0, -100.0}, Eigen::Vector3d::UnitY(), 1.0, c, front()};
}

ContactResult rest(const HeadProbe& h, Placement* placed = nullptr) {
  Placement p;  // Eq. 4: g_c on the nose point at the origin, canonical = scene
  ContactResult r = refine_contact(p, h, Eigen::Vector3d::UnitZ());
  if (placed) *placed = p;
  return r;
}

TEST(NoseRest, SlideAloneCannotClearANoseWiderThanTheBridge) {
  // Today's rule without the ride: the frame slides the whole 15 mm and its rims are still inside the
  // nose (it juts 21.6 mm at the rims' lowest points), so the fit fails a frame a worn frame carries.
  const ContactResult r = rest(head(Nose{}, 0.0));
  EXPECT_EQ(r.rise_mm, 0.0);
  EXPECT_EQ(r.shift_mm, 15.0);
  EXPECT_GT(r.front_penetration_mm, kFrontToleranceMm);
  EXPECT_FALSE(check_front_penetration(true, r.front_penetration_mm, kFrontToleranceMm).passed);
}

TEST(NoseRest, TheFrameRidesUpToWhereTheNoseIsAsWideAsItsBridge) {
  const Nose nose;
  Placement p;
  const ContactResult r = rest(head(nose, ContactOptions{}.max_rise_mm), &p);
  const double truth = -kRimLow + nose.y18();  // 5.75 mm
  // The first height on the 0.5 mm grid at or above the truth, resting on its bridge (the nose's
  // front at the bridge's depth) with nothing inside the face.
  EXPECT_GE(r.rise_mm, truth);
  EXPECT_LE(r.rise_mm, truth + 0.5);
  EXPECT_NEAR(r.shift_mm, 0.0, 0.25);  // the bridge's underside on the nose's front
  EXPECT_EQ(r.front_penetration_mm, 0.0);
  EXPECT_TRUE(check_front_penetration(true, r.front_penetration_mm, kFrontToleranceMm).passed);
  // The bridge stands that much higher, the frame's rotation unchanged (Eq. 5's).
  EXPECT_NEAR(p.transform(1, 3), r.rise_mm, 1e-9);
  EXPECT_TRUE(p.rotation.isIdentity(0.0));
  const Eigen::Matrix3d linear = p.transform.block<3, 3>(0, 0);
  EXPECT_TRUE(linear.isIdentity(0.0));
}

TEST(NoseRest, ANoseNarrowerThanTheBridgeKeepsEqFoursHeight) {
  // 16.7 mm at the rims' lowest points: the frame rests on its bridge where Eq. 4 put it.
  const ContactResult r = rest(head(Nose{14.0, 0.1}, ContactOptions{}.max_rise_mm));
  EXPECT_EQ(r.rise_mm, 0.0);
  EXPECT_NEAR(r.shift_mm, 0.0, 0.25);
  EXPECT_EQ(r.front_penetration_mm, 0.0);
}

TEST(NoseRest, ClearingShiftsBisectTheSlide) {
  // One point 3.3 mm inside a wall at z < 0 clears at the first 0.25 mm step at or past 3.3; a point
  // in the open rests 15 mm back at most (nothing to rest on); a point in a wall 20 mm deep never clears.
  const DensityFn wall = [](const std::vector<Eigen::Vector3f>& p) {
    std::vector<float> s(p.size());
    for (size_t i = 0; i < p.size(); ++i) s[i] = p[i].z() < 0.0f && p[i].x() < 50.0f ? 1.0f : 0.0f;
    return s;
  };
  const PointSets sets = {{{0, 0, -3.3}}, {{100, 0, 0}}, {{0, 0, -20}}};
  const std::vector<double> s = clearing_shifts_mm(wall, 0.5f, sets, Eigen::Vector3d::UnitZ(), 0.25, 15.0);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0], 3.5);
  EXPECT_EQ(s[1], -std::numeric_limits<double>::infinity());
  EXPECT_EQ(s[2], std::numeric_limits<double>::infinity());
  EXPECT_THROW(clearing_shifts_mm(wall, 0.5f, sets, Eigen::Vector3d::UnitZ(), 0.0, 15.0), std::runtime_error);
}

}  // namespace
}  // namespace lorgnette::fit
