// The scale chain (card > irises > mean face, and the policy "auto" it implies), PD's uncertainty,
// each fit-advice rule at and around its band's edges on synthetic numbers, the advice's geometry on
// an analytic head (a nose of known width, a frame placed at a known scale), and the new
// placement.json fields' round trip and refusals.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "fit/advice_geometry.h"
#include "fit/fit_advice.h"
#include "fit/placement_json.h"
#include "fit/scale_chain.h"

namespace lorgnette::fit {
namespace {

TEST(ScaleChain, CardThenIrisThenMeanFace) {
  IrisScale iris;
  iris.ok = true;
  iris.mm_per_unit = 201.0;
  iris.mm_per_unit_uncertainty = 8.6;
  const CaptureScale card{"card", 199.5, 0.8};
  MetricScale m = choose_scale(card, &iris, 214.3);
  EXPECT_EQ(m.source, ScaleSource::kCard);
  EXPECT_EQ(m.mm_per_unit, 199.5);
  EXPECT_EQ(m.mm_per_unit_uncertainty, 0.8);
  EXPECT_EQ(m.mean_face_mm_per_unit, 214.3);
  m = choose_scale(std::nullopt, &iris, 214.3);
  EXPECT_EQ(m.source, ScaleSource::kIris);
  EXPECT_EQ(m.mm_per_unit, 201.0);
  iris.ok = false;
  iris.why = "the two irises disagree";
  m = choose_scale(std::nullopt, &iris, 214.3);
  EXPECT_EQ(m.source, ScaleSource::kMeanFace);
  EXPECT_EQ(m.mm_per_unit, 214.3);
  EXPECT_NEAR(m.relative_uncertainty(), kMeanFaceRelativeUncertainty, 1e-12);
  EXPECT_NE(m.why.find("disagree"), std::string::npos) << m.why;
  EXPECT_EQ(choose_scale(std::nullopt, nullptr, 214.3).source, ScaleSource::kMeanFace);
  for (CaptureScale bad : {CaptureScale{"card", 0.0, 1.0}, CaptureScale{"card", NAN, 1.0},
                           CaptureScale{"card", 200.0, -1.0}, CaptureScale{"card", INFINITY, 0.0}})
    EXPECT_THROW(choose_scale(bad, nullptr, 214.3), std::runtime_error);
  EXPECT_THROW(choose_scale(std::nullopt, nullptr, 0.0), std::runtime_error);
}

TEST(ScaleChain, AutoPolicyAndNames) {
  EXPECT_EQ(resolve_scale_policy(ScalePolicy::kAuto, ScaleSource::kCard), ScalePolicy::kTrueSize);
  EXPECT_EQ(resolve_scale_policy(ScalePolicy::kAuto, ScaleSource::kIris), ScalePolicy::kTrueSize);
  EXPECT_EQ(resolve_scale_policy(ScalePolicy::kAuto, ScaleSource::kMeanFace), ScalePolicy::kStretch);
  EXPECT_EQ(resolve_scale_policy(ScalePolicy::kStretch, ScaleSource::kCard), ScalePolicy::kStretch);
  EXPECT_EQ(resolve_scale_policy(ScalePolicy::kTrueSize, ScaleSource::kMeanFace), ScalePolicy::kTrueSize);
  EXPECT_EQ(parse_scale_policy("auto"), ScalePolicy::kAuto);
  EXPECT_STREQ(scale_policy_name(ScalePolicy::kAuto), "auto");
  for (ScaleSource s : {ScaleSource::kCard, ScaleSource::kIris, ScaleSource::kMeanFace})
    EXPECT_EQ(parse_scale_source(scale_source_name(s)), s);
  EXPECT_THROW(parse_scale_source("ruler"), std::runtime_error);
  // place_glasses needs the policy resolved.
  EXPECT_THROW(place_glasses({}, {{0, 0, 0}, {1, 0, -1}, {-1, 0, -1}, {1, 0, 0}, {-1, 0, 0}, 200.0},
                             ScalePolicy::kAuto),
               std::runtime_error);
}

TEST(ScaleChain, SummarySaysWhetherTheSizeIsReal) {
  std::string s = scale_summary("iris", 201.25, 8.6, 63.2, 2.8, "true-size");
  EXPECT_NE(s.find("the irises: 201.2 +- 8.6 mm per unit; PD 63.2 +- 2.8 mm"), std::string::npos) << s;
  EXPECT_NE(s.find("real size"), std::string::npos) << s;
  s = scale_summary("mean-face", 214.3, 21.4, 64.8, 6.5, "stretch");
  EXPECT_NE(s.find("approximate"), std::string::npos) << s;
  EXPECT_NE(s.find("not its real size"), std::string::npos) << s;
}

// 64 mm at 4.3 %: 2.75 mm; with 0.5 mm per eye centre: sqrt(2.75^2 + 0.5) = 2.84 mm.
TEST(ScaleChain, PdUncertainty) {
  EXPECT_NEAR(pd_uncertainty_mm(64.0, 0.5 / 11.7, 0.0, 0.0), 64.0 * 0.5 / 11.7, 1e-12);
  EXPECT_NEAR(pd_uncertainty_mm(64.0, 0.5 / 11.7, 0.5, 0.5), std::sqrt(std::pow(64.0 * 0.5 / 11.7, 2) + 0.5),
              1e-12);
}

// Each rule: inside its band "good", outside it the rule's words and the distance to the band.
TEST(FitAdvice, FrameWidthRule) {
  EXPECT_EQ(frame_width_rule(140.0, 140.0).verdict, "good");
  EXPECT_EQ(frame_width_rule(145.0, 140.0).verdict, "good");  // the band's edge is inside
  EXPECT_EQ(frame_width_rule(135.0, 140.0).verdict, "good");
  AdviceRule r = frame_width_rule(127.9, 140.0);
  EXPECT_EQ(r.verdict, "too narrow");
  EXPECT_NEAR(r.off_by_mm, 7.1, 1e-9);
  EXPECT_NEAR(r.difference_mm, -12.1, 1e-9);
  r = frame_width_rule(152.0, 140.0);
  EXPECT_EQ(r.verdict, "too wide");
  EXPECT_NEAR(r.off_by_mm, 7.0, 1e-9);
  EXPECT_NE(r.text.find("too wide by 7.0 mm"), std::string::npos) << r.text;
}

TEST(FitAdvice, BridgeRule) {
  EXPECT_EQ(bridge_rule(18.0, 17.0).verdict, "good");
  AdviceRule r = bridge_rule(14.0, 17.5);
  EXPECT_EQ(r.verdict, "too narrow");
  EXPECT_NEAR(r.off_by_mm, 1.5, 1e-9);
  r = bridge_rule(22.0, 17.0);
  EXPECT_EQ(r.verdict, "too wide");
  EXPECT_NEAR(r.off_by_mm, 3.0, 1e-9);
  // A mesh's 18 mm bridge read as a float against a 16 mm nose lies on the band's edge, not 0.0 mm
  // past it; 0.1 mm past it is outside.
  EXPECT_EQ(bridge_rule(double(18.0f + 2e-6f), 16.0).verdict, "good");
  r = bridge_rule(18.1, 16.0);
  EXPECT_EQ(r.verdict, "too wide");
  EXPECT_NE(r.text.find("too wide by 0.1 mm"), std::string::npos) << r.text;
}

TEST(FitAdvice, TempleLengthRule) {
  EXPECT_EQ(temple_length_rule(140.0, 105.0).verdict, "good");  // 35 mm to bend behind the ear
  AdviceRule r = temple_length_rule(125.0, 110.0);              // 15 mm: 10 short of 25
  EXPECT_EQ(r.verdict, "too short");
  EXPECT_NEAR(r.off_by_mm, 10.0, 1e-9);
  r = temple_length_rule(150.0, 100.0);  // 50 mm: 10 beyond 40
  EXPECT_EQ(r.verdict, "too long");
  EXPECT_NEAR(r.off_by_mm, 10.0, 1e-9);
}

TEST(FitAdvice, LensHeightRule) {
  EXPECT_EQ(lens_height_rule(2.0, 40.0).verdict, "good");
  AdviceRule r = lens_height_rule(-5.0, 40.0);  // the pupils 5 mm below the centre line
  EXPECT_EQ(r.verdict, "too high");
  EXPECT_NEAR(r.off_by_mm, 3.0, 1e-9);
  r = lens_height_rule(9.5, 40.0);
  EXPECT_EQ(r.verdict, "too low");
  EXPECT_NEAR(r.off_by_mm, 3.5, 1e-9);
}

TEST(FitAdvice, MissingInputsAreNotJudgedAndMeanFaceIsApproximate) {
  AdviceInputs in;
  in.frame_width_mm = 130, in.temple_width_mm = 128;
  in.why_no_hinges = "the frame's hinges were not found";
  in.approximate = true;
  FitAdvice a = fit_advice(in);
  ASSERT_EQ(a.rules.size(), 4u);
  EXPECT_TRUE(a.approximate);
  EXPECT_EQ(a.rules[0].verdict, "good");
  EXPECT_NE(a.rules[0].text.find("approximate"), std::string::npos);
  for (int k = 1; k < 4; ++k) EXPECT_FALSE(a.rules[k].judged()) << a.rules[k].name;
  EXPECT_NE(a.rules[2].text.find("hinges"), std::string::npos) << a.rules[2].text;
}

// A head at 200 mm per unit whose nose is a wedge: solid where |x| < (half width at the ridge) +
// depth * 0.6, behind a ridge at z = -2 mm (canonical); the frame placed turned 20 degrees about y.
struct WedgeNose {
  Placement placement;
  Eigen::Vector3d g_c{0, 0, 0};
  double mpu = 200.0;
  // The scene point of a canonical mm point (the inverse of canonical_at_true_size).
  Eigen::Vector3d scene(const Eigen::Vector3d& g) const {
    return placement.transform.block<3, 1>(0, 3) + placement.rotation * g / mpu;
  }
  // A head with known points in canonical mm: eye centres, ear rests 100 mm behind the hinges, outer
  // eye corners at +-45 mm.
  AdviceHead known_head() const {
    return {scene({32, 7, -10}),
            scene({-32, 5, -10}),
            scene({66, 4, -105}),
            scene({-66, 4, -105}),
            scene({45, 0, -15}),
            scene({-45, 0, -15}),
            mpu,
            false,
            false,
            Eigen::Vector3d::Zero(),
            Eigen::Vector3d::Zero(),
            ""};
  }
  DensityFn density() const {
    const Placement p = placement;
    const Eigen::Vector3d gc = g_c;
    const double m = mpu;
    return [p, gc, m](const std::vector<Eigen::Vector3f>& pts) {
      std::vector<float> out;
      for (const auto& q : pts) {
        const Eigen::Vector3d c = canonical_at_true_size(p, gc, m, q.cast<double>());
        const double depth = -2.0 - c.z();
        out.push_back(depth > 0 && std::abs(c.x()) < 3.0 + 0.6 * depth ? 100.0f : 0.0f);
      }
      return out;
    };
  }
  WedgeNose() {
    placement.rotation = Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitY()).toRotationMatrix();
    placement.scale = 1.0 / 160.0;  // drawn stretched: the advice must not care
    placement.transform.setIdentity();
    placement.transform.block<3, 3>(0, 0) = placement.scale * placement.rotation;
    placement.transform.block<3, 1>(0, 3) = Eigen::Vector3d(0.1, 0.2, 0.3);
  }
};

// 5 mm behind the ridge the wedge is 2 * (3 + 0.6 * 5) = 12 mm wide; the probe's 0.5 mm steps
// locate each side within a quarter step on average, so within 0.5 mm.
TEST(AdviceGeometry, NoseWidthOfAWedge) {
  WedgeNose w;
  std::string why;
  const double width = nose_width_mm(w.density(), 1.0f, w.placement, w.g_c, w.mpu, 4.0, {}, &why);
  EXPECT_NEAR(width, 12.0, 0.5) << why;
  NoseProbeOptions deep;
  deep.pad_depth_mm = 30.0;  // 2 * (3 + 18) = 42 mm: the cheeks, not a nose
  EXPECT_EQ(nose_width_mm(w.density(), 1.0f, w.placement, w.g_c, w.mpu, 4.0, deep, &why), 0.0);
  EXPECT_NE(why.find("cheeks"), std::string::npos) << why;
  DensityFn empty = [](const std::vector<Eigen::Vector3f>& p) { return std::vector<float>(p.size(), 0.0f); };
  EXPECT_EQ(nose_width_mm(empty, 1.0f, w.placement, w.g_c, w.mpu, 4.0, {}, &why), 0.0);
  EXPECT_NE(why.find("no nose"), std::string::npos) << why;
}

// Known head points (placed through the inverse of canonical_at_true_size) give back their sizes.
TEST(AdviceGeometry, InputsFromAKnownHead) {
  WedgeNose w;
  EXPECT_LT((canonical_at_true_size(w.placement, w.g_c, w.mpu, w.scene({1, 2, 3})) - Eigen::Vector3d(1, 2, 3))
                .norm(),
            1e-9);
  GlassesInput g;
  g.ref.has_hinges = true;
  g.ref.hinge_l = {66, 10, -5};
  g.ref.hinge_r = {-66, 10, -5};
  g.sizes = {135.0, 52.0, 40.0, 3.0, 12.5, 140.0};
  const AdviceHead h = w.known_head();
  // The nose wedge and, from 30 mm behind the bridge, a head 140 mm wide: the temple probe (at the
  // eye corners' height, 15 + 0.25 * 90 mm back) finds its sides at +-70 mm.
  const DensityFn nose = w.density();
  const DensityFn head = [&](const std::vector<Eigen::Vector3f>& pts) {
    std::vector<float> out = nose(pts);
    for (size_t i = 0; i < pts.size(); ++i) {
      const Eigen::Vector3d c = canonical_at_true_size(w.placement, w.g_c, w.mpu, pts[i].cast<double>());
      if (c.z() < -30.0 && std::abs(c.x()) < 70.0 && std::abs(c.y()) < 60.0) out[i] = 100.0f;
    }
    return out;
  };
  const AdviceInputs in = advice_inputs(g, w.placement, h, head, 1.0f);
  EXPECT_NEAR(in.temple_width_mm, 140.0, 0.5) << in.why_no_temples;
  EXPECT_NEAR(in.pupil_above_centre_mm, 6.0 - 3.0, 1e-9);
  EXPECT_NEAR(in.hinge_to_ear_mm, std::hypot(100.0, 6.0), 1e-9);
  EXPECT_NEAR(in.nose_width_mm, 12.0, 0.5) << in.why_no_nose;
  const FitAdvice a = fit_advice(in);
  EXPECT_NEAR(a.rules[0].difference_mm, -5.0, 0.5);  // 135 against 140: on the band's edge
  EXPECT_EQ(a.rules[1].verdict, "good");             // bridge 12.5 on a 12 mm nose
  EXPECT_EQ(a.rules[2].verdict, "good");             // 140 - 100.2 = 39.8 mm behind the ear
  EXPECT_EQ(a.rules[3].verdict, "good");             // the pupils 3 mm above the centre line
  g.sizes.temple_length_mm = 120.0;                  // 19.8 mm behind the ear: 5.2 short of 25
  const AdviceRule t = fit_advice(advice_inputs(g, w.placement, h, head, 1.0f)).rules[2];
  EXPECT_EQ(t.verdict, "too short");
  EXPECT_NEAR(t.off_by_mm, 25.0 - (120.0 - std::hypot(100.0, 6.0)), 1e-9);
}

// The lens height takes the limbus centres when the fit found them, else the eyes' landmark means and
// says so. The known head's landmark means sit 7 and 5 mm up (canonical), its limbus centres 4.5 and
// 3.5 mm lower (the landmark means lay up to 4.9 mm off the painted pupils on the synthetic room
// capture r2_s2), the lenses' centre line 5 mm up: 1 mm above it from the landmarks (good), 3 mm below
// it from the limbus (1 mm beyond the band's -2: too high). Exact up to rounding (1e-9 mm).
TEST(AdviceGeometry, LensHeightFromTheLimbusCentresElseTheLandmarks) {
  WedgeNose w;
  GlassesInput g;
  g.sizes = {135.0, 52.0, 40.0, 5.0, 12.5, 140.0};
  AdviceHead h = w.known_head();
  h.limbus = true;
  h.pupil_l = w.scene({31.5, 2.5, -12});
  h.pupil_r = w.scene({-31.5, 1.5, -12});
  AdviceInputs in = advice_inputs(g, w.placement, h, {}, 1.0f);
  EXPECT_NEAR(in.pupil_above_centre_mm, 2.0 - 5.0, 1e-9);
  EXPECT_TRUE(in.why_pupils_from_landmarks.empty()) << in.why_pupils_from_landmarks;
  AdviceRule r = fit_advice(in).rules[3];
  EXPECT_EQ(r.verdict, "too high");
  EXPECT_NEAR(r.off_by_mm, 1.0, 1e-9);
  EXPECT_EQ(r.text.find("landmarks"), std::string::npos) << r.text;
  // No limbus (closed eyes): the landmark means, and the rule says where its pupils came from.
  h.limbus = false;
  h.why_no_limbus = "no limbus found in the left eye's views";
  in = advice_inputs(g, w.placement, h, {}, 1.0f);
  EXPECT_NEAR(in.pupil_above_centre_mm, 6.0 - 5.0, 1e-9);
  r = fit_advice(in).rules[3];
  EXPECT_EQ(r.verdict, "good");
  EXPECT_NE(r.text.find("pupils from the eyes' landmarks"), std::string::npos) << r.text;
  EXPECT_NE(r.text.find(h.why_no_limbus), std::string::npos) << r.text;
}

// No head beside the temples (only the nose wedge), or a probe that starts inside: no width, why said,
// and the frame-width rule is not judged.
TEST(AdviceGeometry, TempleWidthWithoutAHeadSideIsNotJudged) {
  WedgeNose w;
  const AdviceHead h = w.known_head();
  std::string why;
  EXPECT_EQ(temple_width_mm(w.density(), 1.0f, w.placement, w.g_c, h, {}, &why), 0.0);
  EXPECT_NE(why.find("no side of the head"), std::string::npos) << why;
  const DensityFn full = [](const std::vector<Eigen::Vector3f>& p) {
    return std::vector<float>(p.size(), 9.0f);
  };
  EXPECT_EQ(temple_width_mm(full, 1.0f, w.placement, w.g_c, h, {}, &why), 0.0);
  EXPECT_NE(why.find("starts inside"), std::string::npos) << why;
  GlassesInput g;
  g.sizes = {135.0, 52.0, 40.0, 3.0, 12.5, 140.0};
  const FitAdvice a = fit_advice(advice_inputs(g, w.placement, h, w.density(), 1.0f));
  EXPECT_EQ(a.rules[0].name, "frame_width");
  EXPECT_FALSE(a.rules[0].judged());
}

// The frame the advice measures rests at true size, not where a stretched frame came to rest. The head
// (scene = mm / 200, the frame's axes): a nose whose front lies at z = 0.07 y^2 - 1.5 |x| below the
// bridge (y < 0), widening downwards as a nose does. The frame's lower inner rim corners at
// (+-12, -15, 0) mm clear it at true size (the nose's front there is 2.25 mm behind them), so that frame
// slides in until it touches; stretched 1.306 x they lie at (+-15.7, -19.6) mm, 3.4 mm inside the nose,
// and that frame slides out. The ear rests 100 mm behind the hinges' plane.
TEST(AdviceGeometry, TheAdvicesFrameRestsAtTrueSizeNotWhereTheStretchedOneDid) {
  const double mpu = 200.0;
  GlassesRefPoints g;
  g.g_l = {62, 0, -105}, g.g_r = {-62, 0, -105};
  g.has_hinges = true;
  g.hinge_l = {62, 3, -0.5}, g.hinge_r = {-62, 3, -0.5};
  const PlaceInputs points{Eigen::Vector3d::Zero(),
                           g.g_l / mpu,
                           g.g_r / mpu,
                           Eigen::Vector3d(81, 0, -20) / mpu,
                           Eigen::Vector3d(-81, 0, -20) / mpu,
                           mpu};
  HeadProbe head;
  head.density = [mpu](const std::vector<Eigen::Vector3f>& pts) {
    std::vector<float> out;
    for (const auto& q : pts) {
      const Eigen::Vector3d c = q.cast<double>() * mpu;
      const bool nose = c.y() < 0 && c.z() > -60 && c.z() < 0.07 * c.y() * c.y() - 1.5 * std::abs(c.x());
      out.push_back(nose ? 100.0f : 0.0f);
    }
    return out;
  };
  head.mm_per_unit = mpu;
  head.contact.density_threshold = 1.0f;
  for (double x : {-30.0, -12.0, 12.0, 30.0})
    for (double y : {-15.0, 15.0}) head.frame_points.emplace_back(x, y, 0.0);
  const Eigen::Vector3d fwd(0, 0, 1);
  Placement drawn = place_glasses(g, points, ScalePolicy::kStretch);
  ASSERT_NEAR(drawn.scale * mpu, 162.0 / 124.0, 1e-9);
  const ContactResult stretched = refine_contact(drawn, head, fwd);
  EXPECT_NEAR(stretched.shift_mm, 3.5, 0.3);  // 3.4 mm out, in 0.25 mm steps
  // True size: drawn as it is.
  Placement true_size = place_glasses(g, points, ScalePolicy::kTrueSize);
  refine_contact(true_size, head, fwd);
  const Placement same = advice_placement(g, points, ScalePolicy::kTrueSize, true_size, &head, fwd);
  EXPECT_EQ(same.transform, true_size.transform);
  // Stretched: placed anew at true size and rested: 2-2.25 mm in, not 3.5 mm out.
  const Placement a = advice_placement(g, points, ScalePolicy::kStretch, drawn, &head, fwd);
  EXPECT_NEAR(a.scale, 1.0 / mpu, 1e-12);
  const double shift_mm = a.transform(2, 3) * mpu;
  EXPECT_LE(shift_mm, -2.0);
  EXPECT_GE(shift_mm, -2.25);
  // Hinge to ear on each: the stretched frame's rest puts its hinges 5.5-5.75 mm further from the ears.
  GlassesInput gi;
  gi.ref = g;
  gi.sizes = {135.0, 52.0, 40.0, 3.0, 18.0, 140.0};
  const AdviceHead h{Eigen::Vector3d(30, 0, -10) / mpu,
                     Eigen::Vector3d(-30, 0, -10) / mpu,
                     Eigen::Vector3d(66, 4, -100) / mpu,
                     Eigen::Vector3d(-66, 4, -100) / mpu,
                     Eigen::Vector3d(45, 0, -15) / mpu,
                     Eigen::Vector3d(-45, 0, -15) / mpu,
                     mpu,
                     false,
                     false,
                     Eigen::Vector3d::Zero(),
                     Eigen::Vector3d::Zero(),
                     ""};
  const double at_rest = advice_inputs(gi, a, h, {}, 1.0f).hinge_to_ear_mm;
  EXPECT_NEAR(at_rest, (Eigen::Vector3d(66, 4, -100 - shift_mm) - g.hinge_l).norm(), 1e-6);
  EXPECT_GT(advice_inputs(gi, drawn, h, {}, 1.0f).hinge_to_ear_mm - at_rest, 5.4);
  // Without a head to rest on, the true-size frame stays at the bridge point.
  EXPECT_NEAR(advice_placement(g, points, ScalePolicy::kStretch, drawn, nullptr, fwd).transform(2, 3), 0.0,
              1e-12);
}

TEST(PlacementJsonScale, RoundTripAndRefusals) {
  PlacementFile p;
  p.scale_source = "iris";
  p.mm_per_unit_uncertainty = 8.5;
  p.pd_uncertainty_mm = 2.75;
  p.has_advice = true;
  p.advice = fit_advice({130, 140, 18, 17, 140, 105, 40, 1.0, "", "", "", false, ""});
  nlohmann::json j = to_json(p);
  PlacementFile q = placement_from_json(j);
  EXPECT_EQ(q.scale_source, "iris");
  EXPECT_EQ(q.mm_per_unit_uncertainty, 8.5);
  EXPECT_EQ(q.pd_uncertainty_mm, 2.75);
  ASSERT_TRUE(q.has_advice);
  ASSERT_EQ(q.advice.rules.size(), 4u);
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(q.advice.rules[k].name, p.advice.rules[k].name);
    EXPECT_EQ(q.advice.rules[k].verdict, p.advice.rules[k].verdict);
    EXPECT_EQ(q.advice.rules[k].off_by_mm, p.advice.rules[k].off_by_mm);
    EXPECT_EQ(q.advice.rules[k].text, p.advice.rules[k].text);
  }
  EXPECT_EQ(q.advice.rules[0].verdict, "too narrow");
  // Files before these fields read as unknown.
  nlohmann::json old = j;
  old.erase("scale_source"), old.erase("advice"), old.erase("mm_per_unit_uncertainty");
  q = placement_from_json(old);
  EXPECT_EQ(q.scale_source, "");
  EXPECT_FALSE(q.has_advice);
  auto refused = [&](const std::function<void(nlohmann::json&)>& edit, const std::string& says) {
    nlohmann::json bad = j;
    edit(bad);
    try {
      placement_from_json(bad);
      ADD_FAILURE() << "accepted: " << says;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  refused([](nlohmann::json& b) { b["scale_source"] = "ruler"; }, "scale_source");
  refused([](nlohmann::json& b) { b["mm_per_unit_uncertainty"] = -1.0; }, "negative");
  refused([](nlohmann::json& b) { b["advice"] = 3; }, "advice");
  refused([](nlohmann::json& b) { b["advice"]["rules"][0].erase("verdict"); }, "verdict");
  refused([](nlohmann::json& b) { b["advice"]["rules"][0]["off_by_mm"] = "far"; }, "off_by_mm");
}

}  // namespace
}  // namespace lorgnette::fit
