// The ear-root search (fit/ear_root.h) on an analytic head: a sphere for the skull with a flat-topped
// box for each ear, whose crease with the skull is known exactly; a head without ears; and when
// the fit may use what it finds (both sides at one height, or one side mirrored where the other shows
// nothing or is vetoed).
#include "fit/ear_root.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "fit/hair.h"

namespace lorgnette::fit {
namespace {

constexpr double kSkull = 75.0;                      // sphere radius (mm; 1 scene unit = 1 mm here)
constexpr double kEarTop = 10.0;                     // the ears' flat tops, above the eye corners (y = 0)
constexpr double kEarBack = -25.0, kEarFront = 5.0;  // the ears' extent along z (forward)

// Inside the skull, or inside an ear (a box from x = 60 to 90 mm either side, under its top).
DensityFn head(bool left_ear, bool right_ear) {
  return [=](const std::vector<Eigen::Vector3f>& pts) {
    std::vector<float> d(pts.size());
    for (size_t i = 0; i < pts.size(); ++i) {
      const Eigen::Vector3d p = pts[i].cast<double>();
      const bool skull = p.norm() < kSkull;
      const bool in_ear_box = std::abs(p.x()) > 60.0 && std::abs(p.x()) < 90.0 && p.y() < kEarTop &&
                              p.y() > -40.0 && p.z() > kEarBack && p.z() < kEarFront;
      const bool ear = in_ear_box && ((p.x() > 0 && left_ear) || (p.x() < 0 && right_ear));
      d[i] = skull || ear ? 1e4f : 0.0f;
    }
    return d;
  };
}

EarInputs inputs() {
  EarInputs in;
  in.e_l = {45, 0, 60}, in.e_r = {-45, 0, 60};    // outer eye corners at y = 0
  in.t_l = {74, -5, 12}, in.t_r = {-74, -5, 12};  // temples in front of the ears' roots
  in.d_up = {0, 1, 0}, in.d_fwd = {0, 0, 1};
  return in;
}

// Where the skull's sphere meets the ear's top at depth z.
double crease_x(double z) { return std::sqrt(kSkull * kSkull - kEarTop * kEarTop - z * z); }

TEST(EarRoot, FindsTheCreaseBetweenSkullAndEarTop) {
  const EarInputs in = inputs();
  EarRootOptions o;
  const EarRootSide l =
      find_ear_root(head(true, true), {in.t_l, in.e_l, {1, 0, 0}, in.d_up, in.d_fwd, +1, 1.0}, o);
  ASSERT_TRUE(l.found) << l.why;
  // The ear's top is flat: every depth over it holds the crease at its height. The rest lies
  // rest_behind_front_mm behind the line's front end.
  EXPECT_NEAR(l.point.y(), kEarTop, 1.0);
  EXPECT_NEAR(l.point.z(), in.t_l.z() + l.front_mm - o.line.rest_behind_front_mm, 1e-9);
  EXPECT_NEAR(l.depth_mm, l.front_mm - o.line.rest_behind_front_mm, 1e-9);
  // Laterally at the skull's side, within the slope's span: the crease lies at 69-75 mm over the depths.
  EXPECT_GT(l.point.x(), crease_x(kEarBack) - o.crease.bend_span_mm);
  EXPECT_LT(l.point.x(), crease_x(0.0) + o.crease.bend_span_mm);
  EXPECT_GE(l.slices, int((kEarFront - kEarBack) / o.rays.depth_step_mm) - 2);
  // The line runs from the window's back (the ear reaches behind it) to the ear's front.
  EXPECT_NEAR(l.back_mm, -o.rays.back_mm, 1e-9);
  EXPECT_NEAR(l.front_mm, kEarFront - in.t_l.z(), o.rays.depth_step_mm);
  EXPECT_NEAR(l.front_mm - l.back_mm, (l.slices - 1) * o.rays.depth_step_mm, 1e-9);
  EXPECT_GT(l.bend_deg, 45.0);  // a near-vertical skull side onto a flat top

  // The right side is the mirror image.
  const EarRootSide r =
      find_ear_root(head(true, true), {in.t_r, in.e_r, {1, 0, 0}, in.d_up, in.d_fwd, -1, 1.0}, o);
  ASSERT_TRUE(r.found) << r.why;
  EXPECT_LT((r.point - Eigen::Vector3d(-l.point.x(), l.point.y(), l.point.z())).norm(), 1e-6);
}

TEST(EarRoot, ScaleAndHeightFollowTheInputs) {
  // The same head in scene units of 2 mm and raised by 6 mm: the same rest, in those units.
  const double mpu = 2.0;
  const Eigen::Vector3d lift(0, 6, 0);
  DensityFn mm_head = head(true, true);
  DensityFn scaled = [&](const std::vector<Eigen::Vector3f>& pts) {
    std::vector<Eigen::Vector3f> mm;
    for (const auto& p : pts) mm.push_back((p.cast<double>() * mpu - lift).cast<float>());
    return mm_head(mm);
  };
  const EarInputs in = inputs();
  EarRootOptions o;
  const EarRootSide a = find_ear_root(mm_head, {in.t_l, in.e_l, {1, 0, 0}, in.d_up, in.d_fwd, +1, 1.0}, o);
  const EarRootSide b = find_ear_root(
      scaled, {(in.t_l + lift) / mpu, (in.e_l + lift) / mpu, {1, 0, 0}, in.d_up, in.d_fwd, +1, mpu}, o);
  ASSERT_TRUE(a.found && b.found);
  EXPECT_LT((b.point * mpu - lift - a.point).norm(), 0.2);
}

// The ear's top cut back to 14 mm behind its front (what an exact mesh shows where the ear stands off
// the skull) against the whole top (a NeRF filling that gap): the same front end, so the same rest.
TEST(EarRoot, TheRestFollowsTheRootsFrontNotHowFarBackTheLineRuns) {
  const DensityFn whole = head(true, true);
  const DensityFn cut = [&](const std::vector<Eigen::Vector3f>& pts) {
    std::vector<float> d = whole(pts);
    for (size_t i = 0; i < pts.size(); ++i)
      if (pts[i].z() < kEarFront - 14.0f && std::abs(pts[i].x()) > 60.0f && pts[i].y() < kEarTop &&
          pts[i].cast<double>().norm() >= kSkull)
        d[i] = 0.0f;
    return d;
  };
  const EarInputs in = inputs();
  const EarRootInputs left{in.t_l, in.e_l, {1, 0, 0}, in.d_up, in.d_fwd, +1, 1.0};
  const EarRootOptions o;
  const EarRootSide a = find_ear_root(whole, left, o), b = find_ear_root(cut, left, o);
  ASSERT_TRUE(a.found && b.found) << a.why << " / " << b.why;
  EXPECT_GE(b.back_mm, a.back_mm + 10.0);  // the cut top's line starts 10 mm or more further forward
  EXPECT_NEAR(a.front_mm, b.front_mm, 1e-9);
  EXPECT_NEAR(a.point.z(), b.point.z(), 1e-9);
}

// A NeRF's ear top is soft: the capture sees it only at grazing angles, and its density fades in
// over a few millimetres under the true top (on the procedural heads' NeRFs the rays from above met
// it 2-3 mm under the exact mesh's top at opacity 0.5). Here the ear's density rises linearly from 0
// at its top to kSoftDensity 3 mm under it, so a ray from above reaches opacity q at a depth
// sqrt(6 ln(1 / (1 - q)) / kSoftDensity) under the top: 2.5 mm at 0.5, 1.6 mm at 0.25.
constexpr double kSoftDensity = 0.665;  // per mm, at the ramp's foot
constexpr double kSoftRamp = 3.0;       // mm

double soft_hit_depth(double opacity) {
  return std::sqrt(2.0 * kSoftRamp * -std::log(1.0 - opacity) / kSoftDensity);
}

TEST(EarRoot, ASoftEarTopIsMetAtTheOpacityLevel) {
  const DensityFn sharp = head(true, true);
  const DensityFn soft = [&](const std::vector<Eigen::Vector3f>& pts) {
    std::vector<float> d = sharp(pts);
    for (size_t i = 0; i < pts.size(); ++i) {
      const Eigen::Vector3d p = pts[i].cast<double>();
      if (p.norm() >= kSkull && d[i] > 0.0f)  // the ear outside the skull
        d[i] = float(kSoftDensity * std::min(1.0, (kEarTop - p.y()) / kSoftRamp));
    }
    return d;
  };
  const EarInputs in = inputs();
  const EarRootInputs left{in.t_l, in.e_l, {1, 0, 0}, in.d_up, in.d_fwd, +1, 1.0};
  for (double opacity : {0.5, 0.25}) {
    EarRootOptions o;
    o.rays.opacity = opacity;
    const EarRootSide s = find_ear_root(soft, left, o);
    ASSERT_TRUE(s.found) << s.why;
    // The crease lies on the skull's sharp side within the bend's span, where the ear's soft top
    // meets it: at the analytic depth under the top, within the ray's 0.5 mm sampling.
    EXPECT_NEAR(kEarTop - s.point.y(), soft_hit_depth(opacity), 0.5) << "opacity " << opacity;
  }
  // The default level meets such a top within 2 mm of the truth; 0.5 would not.
  EXPECT_LT(soft_hit_depth(EarRootOptions{}.rays.opacity), 2.0);
  EXPECT_GT(soft_hit_depth(0.5), 2.4);
}

// The rays the search reads, at one depth: the skull's sphere inside the crease, the ear's flat top
// outside it, nothing beyond the ear (x > 90 mm).
TEST(EarRoot, ProfilesAreTheRaysHeights) {
  const EarInputs in = inputs();
  const EarRootOptions o;
  const double depth = -17.0, z = in.t_l.z() + depth;
  const std::vector<EarRootProfile> profiles = ear_root_profiles(
      head(true, true), {in.t_l, in.e_l, {1, 0, 0}, in.d_up, in.d_fwd, +1, 1.0}, o, {depth, depth + 4.0});
  ASSERT_EQ(profiles.size(), 2u);
  const EarRootProfile& p = profiles[0];
  EXPECT_EQ(p.depth_mm, depth);
  ASSERT_EQ(p.lateral_mm.size(), p.height_mm.size());
  int skull = 0, ear = 0, miss = 0;
  for (size_t j = 0; j < p.lateral_mm.size(); ++j) {
    const double x = in.t_l.x() + p.lateral_mm[j], h = p.height_mm[j];
    if (x < crease_x(z) - 1.0) {
      EXPECT_NEAR(h, std::sqrt(kSkull * kSkull - x * x - z * z), o.rays.ray_step_mm) << "x " << x;
      ++skull;
    } else if (x > crease_x(z) + 1.0 && x < 89.5) {
      EXPECT_NEAR(h, kEarTop, o.rays.ray_step_mm) << "x " << x;
      ++ear;
    } else if (x > 90.5) {
      EXPECT_TRUE(std::isnan(h)) << "x " << x;
      ++miss;
    }
  }
  EXPECT_GT(skull, 3);
  EXPECT_GT(ear, 10);
  EXPECT_GT(miss, 10);
}

TEST(EarRoot, NoEarNoRest) {
  const EarInputs in = inputs();
  const EarRootSide s = find_ear_root(
      head(false, false), {in.t_l, in.e_l, {1, 0, 0}, in.d_up, in.d_fwd, +1, 1.0}, EarRootOptions{});
  EXPECT_FALSE(s.found);
  EXPECT_NE(s.why.find("no crease"), std::string::npos) << s.why;
}

TEST(EarRoot, ApplyNeedsAgreeingHeightsOrOneUnopposedSide) {
  const EarInputs in = inputs();
  const EarPoints eq23 = ear_points(in);
  auto apply = [&](const DensityFn& density, const EarVeto& veto = {}) {
    EarPoints ears = eq23;
    EarRoots roots = apply_ear_roots(density, in, {1, 0, 0}, 1.0, EarRootOptions{}, ears, veto);
    return std::make_pair(ears, roots);
  };
  auto [both, roots] = apply(head(true, true));
  ASSERT_TRUE(roots.left.found && roots.right.found) << roots.summary();
  // Symmetric ears: the rests are used as found (their mean height and depth is their own).
  EXPECT_LT((both.f_l - roots.left.point).norm(), 1e-9);
  EXPECT_LT((both.f_r - roots.right.point).norm(), 1e-9);
  EXPECT_NE(roots.summary().find("both ears from the density"), std::string::npos) << roots.summary();

  // No ears, or both sides vetoed (hair over them, say): Eq. 2-3 stand.
  for (const auto& [ears, r] : {apply(head(false, false)), apply(head(true, true), [](const EarRootSide&) {
                                  return std::string("hair");
                                })}) {
    EXPECT_EQ(ears.f_l, eq23.f_l) << r.summary();
    EXPECT_EQ(ears.f_r, eq23.f_r) << r.summary();
    EXPECT_FALSE(r.from_density());
    EXPECT_NE(r.summary().find("Eq. 2-3"), std::string::npos) << r.summary();
  }
  // One side vetoed (hair over that ear): the other side passed the same veto, so its rest stands
  // for both, mirrored.
  {
    auto [ears, r] = apply(head(true, true), [](const EarRootSide& s) {
      return s.point.x() < 0 ? std::string("hair") : std::string();
    });
    EXPECT_TRUE(r.right.vetoed);
    EXPECT_EQ(r.right.why.rfind("hair (a crease ", 0), 0u)
        << r.right.why;  // the veto, then where the crease was
    ASSERT_TRUE(r.left.found) << r.summary();
    EXPECT_EQ(r.use, EarRoots::Use::kMirrored) << r.summary();
    EXPECT_LT((ears.f_l - r.left.point).norm(), 1e-9);
    EXPECT_NEAR(ears.f_r.x(), -ears.f_l.x(), 1e-9);
    EXPECT_NEAR(ears.f_r.y(), ears.f_l.y(), 1e-9);
    EXPECT_NEAR(ears.f_r.z(), ears.f_l.z(), 1e-9);
  }

  // One ear shown, the other side empty (not vetoed): the found rest stands for both, mirrored. The
  // inputs are symmetric, so the right rest is the left one's mirror image.
  {
    auto [ears, r] = apply(head(true, false));
    ASSERT_TRUE(r.left.found && !r.right.found) << r.summary();
    EXPECT_EQ(r.use, EarRoots::Use::kMirrored);
    EXPECT_NE(r.summary().find("mirrored"), std::string::npos) << r.summary();
    EXPECT_LT((ears.f_l - r.left.point).norm(), 1e-9);
    EXPECT_NEAR(ears.f_r.x(), -ears.f_l.x(), 1e-9);
    EXPECT_NEAR(ears.f_r.y(), ears.f_l.y(), 1e-9);
    EXPECT_NEAR(ears.f_r.z(), ears.f_l.z(), 1e-9);
  }
  // ... but not when it lies higher than one side alone may (hair makes creases high on the head).
  {
    EarRootOptions low;
    low.pair.plausible_highest_mm = kEarTop - 5.0;
    EarPoints ears = eq23;
    EarRoots r = apply_ear_roots(head(true, false), in, {1, 0, 0}, 1.0, low, ears);
    EXPECT_FALSE(r.from_density()) << r.summary();
    EXPECT_NE(r.summary().find("allowed for one side alone"), std::string::npos) << r.summary();
    EXPECT_EQ(ears.f_r, eq23.f_r);
  }

  // The right ear 6 mm lower than the left: both rests at the middle height, each at its own width.
  // The right half of the head (skull and ear) moved by `by` (mm; y up, z forward).
  auto right_half_moved = [full = head(true, true)](const Eigen::Vector3f& by) {
    return DensityFn([=](const std::vector<Eigen::Vector3f>& pts) {
      std::vector<Eigen::Vector3f> moved = pts;
      for (auto& p : moved)
        if (p.x() < 0) p -= by;
      return full(moved);
    });
  };
  {
    EarPoints lv = eq23;
    EarRoots six =
        apply_ear_roots(right_half_moved({0.0f, -6.0f, 0.0f}), in, {1, 0, 0}, 1.0, EarRootOptions{}, lv);
    ASSERT_TRUE(six.left.found && six.right.found) << six.summary();
    EXPECT_NEAR(six.left.point.y() - six.right.point.y(), 6.0, 1.0);
    EXPECT_NEAR(lv.f_l.y(), 0.5 * (six.left.point.y() + six.right.point.y()), 1e-9);
    EXPECT_NEAR(lv.f_r.y(), lv.f_l.y(), 1e-9);
    EXPECT_NEAR(lv.f_l.x(), six.left.point.x(), 1e-9);
    EXPECT_NEAR(lv.f_r.x(), six.right.point.x(), 1e-9);
  }
  // The right ear 16 mm further forward: the depths are averaged (along the root's flat top a depth
  // is loosely defined), each rest at its own width.
  {
    EarPoints lv = eq23;
    EarRootOptions wide;  // a window reaching 10 mm in front of the temples, to hold the moved ear whole
    wide.rays.front_mm = 10.0;
    EarRoots fwd = apply_ear_roots(right_half_moved({0.0f, 0.0f, 16.0f}), in, {1, 0, 0}, 1.0, wide, lv);
    ASSERT_TRUE(fwd.left.found && fwd.right.found) << fwd.summary();
    EXPECT_NEAR(fwd.right.point.z() - fwd.left.point.z(), 16.0, 2.0);
    EXPECT_NEAR(lv.f_l.z(), 0.5 * (fwd.left.point.z() + fwd.right.point.z()), 1e-9);
    EXPECT_NEAR(lv.f_r.z(), lv.f_l.z(), 1e-9);
    EXPECT_EQ(fwd.use, EarRoots::Use::kBoth);
  }
  // The right ear 18 mm higher: the two rests no longer agree within the 15 mm allowed.
  EarPoints ears = eq23;
  EarRoots r =
      apply_ear_roots(right_half_moved({0.0f, 18.0f, 0.0f}), in, {1, 0, 0}, 1.0, EarRootOptions{}, ears);
  EXPECT_FALSE(r.left.found || r.right.found) << r.summary();
  EXPECT_NE(r.left.why.find("apart"), std::string::npos) << r.left.why;
  EXPECT_EQ(ears.f_l, eq23.f_l);
}

// A higher ledge in front of each ear (hair standing out over the temple, say: from the ears' front to
// the temple, its top 8 mm over theirs; 4 depths of the window) makes a second, higher line of creases.
constexpr double kLedgeTop = kEarTop + 8.0;
DensityFn head_with_ledge() {
  return [ears = head(true, true)](const std::vector<Eigen::Vector3f>& pts) {
    std::vector<float> d = ears(pts);
    for (size_t i = 0; i < pts.size(); ++i) {
      const Eigen::Vector3d p = pts[i].cast<double>();
      if (std::abs(p.x()) > 60.0 && std::abs(p.x()) < 85.0 && p.y() < kLedgeTop && p.y() > -40.0 &&
          p.z() >= kEarFront && p.z() < 13.0)
        d[i] = 1e4f;
    }
    return d;
  };
}

// Counted as a line in its own right (short_line_slices at most its 4 depths): a veto that refuses it
// leaves the ear's own line, under it; and that line must then lie where ears do.
TEST(EarRoot, TakesTheHighestLineTheVetoAccepts) {
  const EarInputs in = inputs();
  const DensityFn with_ledge = head_with_ledge();
  EarRootOptions any_length;
  any_length.line.short_line_slices = 1;
  const EarRootSide highest =
      find_ear_root(with_ledge, {in.t_l, in.e_l, {1, 0, 0}, in.d_up, in.d_fwd, +1, 1.0}, any_length);
  ASSERT_TRUE(highest.found) << highest.why;
  EXPECT_NEAR(highest.point.y(), kLedgeTop, 1.0);  // without a veto: the ledge, the highest line

  const EarVeto ledge_is_hair = [&](const EarRootSide& s) {
    return s.point.y() > kEarTop + 4.0 ? std::string("hair") : std::string();
  };
  EarPoints points = ear_points(in);
  EarRoots r = apply_ear_roots(with_ledge, in, {1, 0, 0}, 1.0, any_length, points, ledge_is_hair);
  ASSERT_EQ(r.use, EarRoots::Use::kBoth) << r.summary();
  EXPECT_NEAR(r.left.point.y(), kEarTop, 1.0);
  EXPECT_LT(r.left.point.z(), kEarFront);
  EXPECT_EQ(r.left.higher_vetoed, 1);
  EXPECT_NE(r.summary().find("higher line(s) vetoed"), std::string::npos) << r.summary();

  // Ears allowed no higher than 5 mm over the eye corners: the line under the hair is refused too,
  // and with it the side.
  EarRootOptions low = any_length;
  low.pair.plausible_highest_mm = kEarTop - 5.0;
  EarPoints eq23 = ear_points(in), kept = eq23;
  r = apply_ear_roots(with_ledge, in, {1, 0, 0}, 1.0, low, kept, ledge_is_hair);
  EXPECT_FALSE(r.from_density()) << r.summary();
  EXPECT_TRUE(r.left.vetoed && r.right.vetoed);
  EXPECT_NE(r.left.why.find("the 1 lower line(s) of creases too (the highest: it lies under hair"),
            std::string::npos)
      << r.left.why;
  EXPECT_EQ(kept.f_l, eq23.f_l);
}

// With the default short_line_slices the ledge's 4 depths are hair's edge over the ear's longer root:
// the root comes first with no veto at all, and the ledge stays as the next line.
TEST(EarRoot, AShortLineAboveTheRootFollowsIt) {
  const EarInputs in = inputs();
  const EarRootOptions o;
  const std::vector<EarRootSide> lines =
      find_ear_root_lines(head_with_ledge(), {in.t_l, in.e_l, {1, 0, 0}, in.d_up, in.d_fwd, +1, 1.0}, o);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_NEAR(lines[0].point.y(), kEarTop, 1.0);
  EXPECT_GE(lines[0].slices, o.line.short_line_slices);
  EXPECT_NEAR(lines[1].point.y(), kLedgeTop, 1.0);
  EXPECT_LT(lines[1].slices, o.line.short_line_slices);
  EarPoints points = ear_points(in);
  const EarRoots r = apply_ear_roots(head_with_ledge(), in, {1, 0, 0}, 1.0, o, points);
  ASSERT_EQ(r.use, EarRoots::Use::kBoth) << r.summary();
  EXPECT_NEAR(r.left.point.y(), kEarTop, 1.0);
  EXPECT_NEAR(r.right.point.y(), kEarTop, 1.0);
  EXPECT_LT(r.left.point.z(), kEarFront);
}

// The left ear's back third raised 7 mm (a fold of hair lying on it, say): the left side's highest
// line runs along that back (6 depths, 28-38 mm behind the temple) over the root's own, in front of
// it. The right half of the head sits 10 mm further forward, so the right root's line lies ~17 mm in
// front of the back line and ~2 mm from the left root's.
DensityFn head_with_raised_back() {
  const DensityFn ears = head(true, true);
  return [=](const std::vector<Eigen::Vector3f>& pts) {
    std::vector<Eigen::Vector3f> moved = pts;
    for (auto& p : moved)
      if (p.x() < 0) p.z() -= 10.0f;
    std::vector<float> d = ears(moved);
    for (size_t i = 0; i < pts.size(); ++i) {
      const Eigen::Vector3d p = pts[i].cast<double>();
      if (p.x() > 60.0 && p.x() < 90.0 && p.y() < kEarTop + 7.0 && p.y() > -40.0 && p.z() > kEarBack &&
          p.z() < -12.0)
        d[i] = 1e4f;
    }
    return d;
  };
}

// The left ear's top only behind z = -16 (a fragment of its root: 4 depths at the window's back, as
// seed 13's NeRF showed where hair met the ear), the right ear whole: the rests' depth is the right
// line's alone, their height the mean of both.
TEST(EarRoot, AShortLineOppositeALongOneGivesNoDepth) {
  const DensityFn whole = head(true, true);
  const DensityFn density = [&](const std::vector<Eigen::Vector3f>& pts) {
    std::vector<float> d = whole(pts);
    for (size_t i = 0; i < pts.size(); ++i)
      if (pts[i].x() > 0.0f && pts[i].z() > -16.0f && pts[i].cast<double>().norm() >= kSkull) d[i] = 0.0f;
    return d;
  };
  const EarInputs in = inputs();
  const EarRootOptions o;
  EarPoints ears = ear_points(in);
  const EarRoots roots = apply_ear_roots(density, in, {1, 0, 0}, 1.0, o, ears);
  ASSERT_TRUE(roots.left.found && roots.right.found) << roots.summary();
  ASSERT_LT(roots.left.slices, o.line.short_line_slices);
  ASSERT_GE(roots.right.slices, o.line.short_line_slices);
  // The fragment's own rest lies at its back end, 10 mm or more behind the whole line's.
  EXPECT_LT(roots.left.point.z(), roots.right.point.z() - 10.0);
  EXPECT_NEAR(ears.f_l.z(), roots.right.point.z(), 1e-9);
  EXPECT_NEAR(ears.f_r.z(), roots.right.point.z(), 1e-9);
  const double height = 0.5 * (roots.left.point.y() + roots.right.point.y());
  EXPECT_NEAR(ears.f_l.y(), height, 1e-9);
  EXPECT_NEAR(ears.f_r.y(), height, 1e-9);
  EXPECT_NEAR(ears.f_l.x(), roots.left.point.x(), 1e-9);  // each at its own width
  EXPECT_NE(roots.summary().find("the left side's line holds"), std::string::npos) << roots.summary();
}

// Each side's first line 17 mm apart in depth, over the 12 allowed: the pair that agrees (the left
// root's line, second on its side, and the right's) is used; with no limit, or no stand-in long
// enough, the first lines.
TEST(EarRoot, APairOfLinesThatAgreeInDepthIsUsed) {
  const EarInputs in = inputs();
  const DensityFn density = head_with_raised_back();
  const EarRootOptions o;
  const std::vector<EarRootSide> left =
      find_ear_root_lines(density, {in.t_l, in.e_l, {1, 0, 0}, in.d_up, in.d_fwd, +1, 1.0}, o);
  ASSERT_EQ(left.size(), 2u);
  EXPECT_NEAR(left[0].point.y(), kEarTop + 7.0, 1.0);
  EXPECT_LT(left[0].point.z(), -12.0);
  EXPECT_NEAR(left[1].point.y(), kEarTop, 1.0);
  EXPECT_GT(left[1].point.z(), -12.0);

  EarPoints ears = ear_points(in);
  const EarRoots r = apply_ear_roots(density, in, {1, 0, 0}, 1.0, o, ears);
  ASSERT_EQ(r.use, EarRoots::Use::kBoth) << r.summary();
  EXPECT_NEAR(r.left.point.y(), kEarTop, 1.0);
  EXPECT_NEAR(r.left.point.z(), left[1].point.z(), 1e-9);
  EXPECT_EQ(r.left.passed_over, 1);
  EXPECT_EQ(r.right.passed_over, 0);
  EXPECT_LE(std::abs(r.left.point.z() - r.right.point.z()), o.pair.max_depth_gap_mm);
  EXPECT_NEAR(ears.f_l.z(), 0.5 * (r.left.point.z() + r.right.point.z()), 1e-9);
  EXPECT_NE(r.summary().find("which agree, were used"), std::string::npos) << r.summary();
  EXPECT_NE(r.summary().find("1 higher line(s) passed over"), std::string::npos) << r.summary();

  EarRootOptions any_gap;
  any_gap.pair.max_depth_gap_mm = std::numeric_limits<double>::infinity();
  EarPoints first = ear_points(in);
  const EarRoots f = apply_ear_roots(density, in, {1, 0, 0}, 1.0, any_gap, first);
  ASSERT_EQ(f.use, EarRoots::Use::kBoth) << f.summary();
  EXPECT_NEAR(f.left.point.z(), left[0].point.z(), 1e-9);
  EXPECT_GT(std::abs(f.left.point.z() - f.right.point.z()), o.pair.max_depth_gap_mm);
  EXPECT_EQ(f.left.passed_over, 0);

  // A stand-in must span short_line_slices depths: asked for more than the left root's, the first
  // lines stay (no line here reaches that length, so the order is the heights').
  EarRootOptions long_lines;
  long_lines.line.short_line_slices = left[1].slices + 1;
  EarPoints kept = ear_points(in);
  const EarRoots k = apply_ear_roots(density, in, {1, 0, 0}, 1.0, long_lines, kept);
  ASSERT_EQ(k.use, EarRoots::Use::kBoth) << k.summary();
  EXPECT_NEAR(k.left.point.z(), left[0].point.z(), 1e-9);
  EXPECT_EQ(k.summary().find("which agree"), std::string::npos) << k.summary();

  // A line the veto refuses never stands in: with the left root's line refused, the first lines stay.
  EarPoints vetoed = ear_points(in);
  const EarRoots v = apply_ear_roots(density, in, {1, 0, 0}, 1.0, o, vetoed, [](const EarRootSide& s) {
    return s.point.x() > 0 && s.point.z() > -12.0 ? std::string("hair") : std::string();
  });
  ASSERT_EQ(v.use, EarRoots::Use::kBoth) << v.summary();
  EXPECT_NEAR(v.left.point.z(), left[0].point.z(), 1e-9);
  EXPECT_EQ(v.left.passed_over, 0);
}

TEST(EarRoot, RejectsBadInputs) {
  const EarInputs in = inputs();
  EarRootOptions o;
  EXPECT_THROW(find_ear_root(head(true, true), {in.t_l, in.e_l, {1, 0, 0}, in.d_up, in.d_fwd, +1, 0.0}, o),
               std::invalid_argument);
  EXPECT_THROW(find_ear_root(head(true, true), {in.t_l, in.e_l, {1, 0, 0}, in.d_up, in.d_fwd, 0, 1.0}, o),
               std::invalid_argument);
  o.rays.ray_step_mm = 0.0;
  EXPECT_THROW(find_ear_root(head(true, true), {in.t_l, in.e_l, {1, 0, 0}, in.d_up, in.d_fwd, +1, 1.0}, o),
               std::invalid_argument);
}

// Hair over the ear's root (synth paints its hairline 1-3 mm above the ear's top, and a real head's
// hair often hangs there): hair-dark within `hair_mm` outside the crease, from 1 mm under the ear's
// top upwards; skin elsewhere. The hair test must still see the ear's top as skin; an ear whose whole
// top lies under hair must read as hair.
TEST(EarRoot, TheHairTestReadsTheEarsTopAcrossItsWidth) {
  const EarInputs in = inputs();
  const EarRootOptions o;
  const EarRootSide l =
      find_ear_root(head(true, true), {in.t_l, in.e_l, {1, 0, 0}, in.d_up, in.d_fwd, +1, 1.0}, o);
  ASSERT_TRUE(l.found) << l.why;
  ASSERT_FALSE(l.ear_top.empty());
  const Eigen::Vector3f skin(0.6f, 0.4f, 0.3f), hair(0.035f, 0.022f, 0.015f);
  auto painted = [&](double hair_mm) -> ColourFn {
    return [=](const std::vector<Eigen::Vector3f>& p, const std::vector<Eigen::Vector3f>&) {
      std::vector<Eigen::Vector3f> c;
      for (const auto& q : p)
        c.push_back(q.y() > kEarTop - 1.0 && q.x() < crease_x(q.z()) + hair_mm ? hair : skin);
      return c;
    };
  };
  const double darkest = HairOptions{}.max_luminance_ratio * luminance(skin);
  // Hair 4.5 mm over the top: the one point 3 mm out that the test once read is hair at every depth,
  // the top beyond it skin.
  const ColourFn over_root = painted(4.5);
  for (const auto& depth : l.ear_top) {
    ASSERT_FALSE(depth.empty());
    EXPECT_EQ(over_root({depth.front().cast<float>()}, {Eigen::Vector3f(0, -1, 0)})[0], hair);
  }
  const std::optional<double> seen = ear_top_luminance(over_root, l.ear_top, in.d_up);
  ASSERT_TRUE(seen.has_value());
  EXPECT_NEAR(*seen, luminance(skin), 1e-6);
  // Hair over the whole top (the ear under it): hair.
  const std::optional<double> under = ear_top_luminance(painted(30.0), l.ear_top, in.d_up);
  ASSERT_TRUE(under.has_value());
  EXPECT_LT(*under, darkest);
  EXPECT_NEAR(*under, luminance(hair), 1e-6);
  // No colour: no answer.
  EXPECT_FALSE(ear_top_luminance(ColourFn{}, l.ear_top, in.d_up).has_value());
}

}  // namespace
}  // namespace lorgnette::fit
