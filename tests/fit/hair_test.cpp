// Hair is not skin (fit/hair.h) on an analytic head: a skin-coloured ball of radius R whose centre
// lies behind the hinges, inside a dark hair shell out to radius H, both equally dense; the temples
// are the straight segments of temple_fit_test.cpp (hinges at x = +-70 mm, z = 0, running back
// along -z), so the spread that clears a ball of radius R by the allowed depth L has the closed form
//   theta*(R) = phi0 - acos((R - L) / D),  D = hypot(hx, zc), phi0 = atan2(|zc|, hx).
// With hair counted as solid the temples must clear the shell (H = 110 mm needs ~36 deg, beyond the
// 25 deg limit: the "NOT ok" of a long-haired capture); with the hair test they rest on the skin
// ball, at theta*(R) to within one search step (0.25 deg) plus 0.01 deg. A skin-coloured shell (a
// large head, no hair) must still block them, and so must a skin-coloured ear inside the hair.
#include "fit/hair.h"

#include <gtest/gtest.h>

#include <cmath>

#include "fit/temple_fit.h"

namespace lorgnette::fit {
namespace {

constexpr double kHx = 70.0, kLength = 120.0, kLimit = 0.5;
const Eigen::Vector3f kSkin(0.62f, 0.38f, 0.27f);   // linear RGB of a light skin (luminance ~0.43)
const Eigen::Vector3f kHair(0.03f, 0.02f, 0.015f);  // dark brown hair (luminance ~0.02)

// A ball of skin (radius r) under a shell of `shell` colour out to radius h, optionally with a
// skin-coloured ear (ball of radius 8 mm) at `ear`, all at density 100 per mm.
struct Head {
  Eigen::Vector3d c{0, 0, -90};
  double r = 75.0, h = 110.0;
  Eigen::Vector3f shell = kHair;
  std::optional<Eigen::Vector3d> ear;

  bool in_ear(const Eigen::Vector3f& p) const { return ear && (p.cast<double>() - *ear).norm() < 8.0; }
  DensityFn density() const {
    return [*this](const std::vector<Eigen::Vector3f>& p) {
      std::vector<float> s(p.size());
      for (size_t i = 0; i < p.size(); ++i)
        s[i] = ((p[i].cast<double>() - c).norm() < h || in_ear(p[i])) ? 100.0f : 0.0f;
      return s;
    };
  }
  ColourFn colour() const {
    return [*this](const std::vector<Eigen::Vector3f>& p, const std::vector<Eigen::Vector3f>& d) {
      EXPECT_EQ(p.size(), d.size());
      std::vector<Eigen::Vector3f> out(p.size());
      for (size_t i = 0; i < p.size(); ++i)
        out[i] = ((p[i].cast<double>() - c).norm() < r || in_ear(p[i])) ? kSkin : shell;
      return out;
    };
  }
};

std::vector<Eigen::Vector3d> temples() {
  std::vector<Eigen::Vector3d> pts;
  for (double t = 0.0; t <= kLength; t += 0.25)
    for (double s : {1.0, -1.0}) pts.emplace_back(s * kHx, 0.0, -t);
  return pts;
}

HeadProbe probe(const Head& head) {
  ContactOptions contact;
  contact.density_threshold = 10.0f;
  return HeadProbe{head.density(), head.c, Eigen::Vector3d::UnitY(), 1.0, contact, temples()};
}

TempleFitResult fit(const HeadProbe& head) {
  TempleFitInputs in;
  in.hinge_l = {kHx, 0, 0};
  in.hinge_r = {-kHx, 0, 0};
  return fit_temples(in, head, kLimit, TempleFitOptions{});
}

double needed_deg(double r) {
  return (std::atan2(90.0, kHx) - std::acos((r - kLimit) / std::hypot(kHx, 90.0))) * 180.0 / M_PI;
}

// The skin tone as fit_glasses reads it: points on the skin ball's front (the "nose line").
SkinTone tone(const Head& head) {
  std::vector<Eigen::Vector3d> nose;
  for (double y : {-6.0, -2.0, 2.0, 6.0}) nose.push_back(head.c + Eigen::Vector3d(0, y, head.r - 0.5));
  std::optional<SkinTone> t = skin_tone(head.colour(), nose, -Eigen::Vector3d::UnitZ());
  EXPECT_TRUE(t.has_value());
  return t.value_or(SkinTone{});
}

TEST(Hair, TemplesRestOnTheSkinUnderDarkHair) {
  Head head;
  ASSERT_GT(needed_deg(head.h), 25.0);  // the shell alone cannot be cleared
  const TempleFitResult with_hair = fit(probe(head));
  EXPECT_FALSE(with_hair.left.clear);  // the failure the hair test removes
  EXPECT_EQ(with_hair.left.spread_deg, 25.0);

  HeadProbe skin = probe(head);
  skin.density = density_without_hair(skin, head.colour(), tone(head), HairOptions{});
  const TempleFitResult res = fit(skin);
  const double want = needed_deg(head.r);
  for (const TempleSideFit* s : {&res.left, &res.right}) {
    EXPECT_TRUE(s->clear);
    EXPECT_GE(s->spread_deg, want - 0.01);
    EXPECT_LE(s->spread_deg, want + 0.25 + 0.01);
    EXPECT_NEAR(s->penetration_before_mm, head.r - kHx, 0.25);  // the skin ball's depth, not the shell's
  }
}

TEST(Hair, SkinColouredVolumeStillBlocks) {
  // No hair: the outer shell has the skin's colour (a large head); the test must change nothing.
  Head head;
  head.shell = kSkin;
  HeadProbe skin = probe(head);
  skin.density = density_without_hair(skin, head.colour(), tone(head), HairOptions{});
  const TempleFitResult res = fit(skin), plain = fit(probe(head));
  EXPECT_EQ(res.left.spread_deg, plain.left.spread_deg);
  EXPECT_EQ(res.left.penetration_mm, plain.left.penetration_mm);
  EXPECT_FALSE(res.left.clear);
}

TEST(Hair, AnEarInsideTheHairStillBlocks) {
  // A skin-coloured ear sticking out of the skin ball into the hair, on the left temple's rigid path
  // (x = 70, 100 mm behind the hinge): the left temple must spread past it, the right one (no ear)
  // rests on the skin ball alone.
  Head head;
  head.ear = Eigen::Vector3d(kHx + 2.0, 0.0, -100.0);
  HeadProbe skin = probe(head);
  skin.density = density_without_hair(skin, head.colour(), tone(head), HairOptions{});
  const TempleFitResult res = fit(skin);
  EXPECT_NEAR(res.left.penetration_before_mm, 10.0, 0.5);  // the ear's depth below the temple
  EXPECT_GT(res.left.spread_deg, res.right.spread_deg + 1.0);
  EXPECT_TRUE(res.left.clear);
  EXPECT_LE(res.right.spread_deg, needed_deg(head.r) + 0.26);
}

TEST(Hair, NoColourMeansNoHairTest) {
  Head head;
  const ColourFn none = [](const std::vector<Eigen::Vector3f>&, const std::vector<Eigen::Vector3f>&) {
    return std::vector<Eigen::Vector3f>{};
  };
  EXPECT_FALSE(skin_tone(none, {head.c}, Eigen::Vector3d::UnitZ()).has_value());
  EXPECT_FALSE(skin_tone(head.colour(), {}, Eigen::Vector3d::UnitZ()).has_value());
  // A black "skin" gives nothing to compare hair with.
  const ColourFn black = [](const std::vector<Eigen::Vector3f>& p, const std::vector<Eigen::Vector3f>&) {
    return std::vector<Eigen::Vector3f>(p.size(), Eigen::Vector3f::Zero());
  };
  EXPECT_FALSE(skin_tone(black, {head.c}, Eigen::Vector3d::UnitZ()).has_value());
}

TEST(Hair, SkinToneIsTheLowerMedian) {
  // Four nose-line samples, one a specular highlight and one a dark nostril: the tone is the lower
  // median of the luminance-sorted samples.
  const std::vector<Eigen::Vector3f> cols = {
      {0.9f, 0.9f, 0.9f}, {0.5f, 0.3f, 0.2f}, {0.05f, 0.03f, 0.02f}, {0.6f, 0.35f, 0.25f}};
  const ColourFn colour = [&](const std::vector<Eigen::Vector3f>& p, const std::vector<Eigen::Vector3f>&) {
    return std::vector<Eigen::Vector3f>(cols.begin(), cols.begin() + p.size());
  };
  std::optional<SkinTone> t =
      skin_tone(colour, std::vector<Eigen::Vector3d>(4, Eigen::Vector3d::Zero()), Eigen::Vector3d::UnitZ());
  ASSERT_TRUE(t);
  EXPECT_EQ(t->samples, 4);
  EXPECT_EQ(t->rgb, cols[1]);
  EXPECT_NEAR(t->luminance, luminance(cols[1]), 1e-12);
}

}  // namespace
}  // namespace lorgnette::fit
