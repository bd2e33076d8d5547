// The fit's input checks and its verdict's tolerances (fit/input_checks.h), both ways: a broken input
// fails with its reason, a good one passes. The landmarks' opacity is judged on an analytic head (an
// opaque ball, 200 mm per scene unit, landmarks on its front) against a ball with a tunnel through
// its nose and against landmarks floating in front of it; the checks reach placement.json through
// make_placement_file and read back.
#include "fit/input_checks.h"

#include <gtest/gtest.h>

#include <cmath>

#include "fit/fit.h"
#include "fit/fit_placement.h"
#include "fit/placement_json.h"

namespace lorgnette::fit {
namespace {

constexpr double kRadius = 0.5, kMmPerUnit = 200.0;

ColourFn constant_colour(float v) {
  return [v](const std::vector<Eigen::Vector3f>& p, const std::vector<Eigen::Vector3f>&) {
    return std::vector<Eigen::Vector3f>(p.size(), Eigen::Vector3f(v, v, v));
  };
}

TEST(InputChecks, NoseLineMustReadSkin) {
  const std::vector<Eigen::Vector3d> nose = {{0, 0.1, 0.5}, {0, 0.05, 0.52}, {0, 0, 0.55}, {0, -0.05, 0.57}};
  // The darkest lit skin (sRGB ~40/255 = linear 0.021) passes; the 0.000 fails with its reason.
  const InputCheck dark_skin = check_nose_skin(constant_colour(0.021f), nose, {0, 0, -1});
  EXPECT_TRUE(dark_skin.checked);
  EXPECT_TRUE(dark_skin.passed);
  EXPECT_NEAR(dark_skin.value, 0.021, 1e-6);
  const InputCheck black = check_nose_skin(constant_colour(0.0f), nose, {0, 0, -1});
  EXPECT_TRUE(black.checked);
  EXPECT_FALSE(black.passed);
  EXPECT_NE(black.reason.find("reads no skin"), std::string::npos);
  EXPECT_NE(black.reason.find("Film again"), std::string::npos);
  // A bright specular outlier does not lift a black nose line (lower median).
  ColourFn spec = [](const std::vector<Eigen::Vector3f>& p, const std::vector<Eigen::Vector3f>&) {
    std::vector<Eigen::Vector3f> c(p.size(), Eigen::Vector3f::Zero());
    c[0] = Eigen::Vector3f(1, 1, 1);
    return c;
  };
  EXPECT_FALSE(check_nose_skin(spec, nose, {0, 0, -1}).passed);
  // A source without colour (a mesh) is not judged.
  ColourFn none = [](const std::vector<Eigen::Vector3f>&, const std::vector<Eigen::Vector3f>&) {
    return std::vector<Eigen::Vector3f>{};
  };
  const InputCheck unchecked = check_nose_skin(none, nose, {0, 0, -1});
  EXPECT_FALSE(unchecked.checked);
  EXPECT_TRUE(unchecked.passed);
}

struct Ball {
  double tunnel = 0.0;  // radius of a hole along z through x = 0, y in the nose's band
  DensityFn density() const {
    return [t = tunnel](const std::vector<Eigen::Vector3f>& p) {
      std::vector<float> s(p.size());
      for (size_t i = 0; i < p.size(); ++i) {
        const bool hole = std::hypot(p[i].x(), p[i].y() + 0.05) < t;
        s[i] = p[i].norm() < kRadius && !hole ? 500.0f : 0.0f;  // 0.5 mm steps: 0.25 optical depth each
      }
      return s;
    };
  }
};

// 68 points: the inner ones (17-67) on the ball's front within 35 deg of +z, the nose line (27-35)
// down the middle; every point seen by three cameras in front.
struct Face {
  std::vector<TriangulatedPoint> points = std::vector<TriangulatedPoint>(68);
  std::vector<Camera> cameras;
  explicit Face(double lift_mm = 0.0) {
    for (int k = 17; k < 68; ++k) {
      double x = 0.0, y = -0.05 - 0.02 * (k - 27);
      if (k < 27 || k > 35) {
        const double a = 2.0 * M_PI * k / 41.0;
        x = 0.25 * std::cos(a), y = 0.25 * std::sin(a);
      }
      const double z = std::sqrt(kRadius * kRadius - x * x - y * y) + lift_mm / kMmPerUnit;
      points[k].position = {x, y, z};
      points[k].ok = true;
      points[k].inliers = {0, 1, 2};
    }
    for (double yaw : {-0.3, 0.0, 0.3}) {
      Camera c{};
      c.c2w[3] = float(3.0 * std::sin(yaw)), c.c2w[11] = float(3.0 * std::cos(yaw));
      cameras.push_back(c);
    }
  }
};

TEST(InputChecks, LandmarksMustLieOnDensity) {
  const InputCheck whole = check_landmarks_solid(Ball{}.density(), Face().cameras, Face().points, kMmPerUnit);
  EXPECT_TRUE(whole.checked);
  EXPECT_TRUE(whole.passed) << whole.reason;
  EXPECT_EQ(whole.value, 0.0);
  // Landmarks 10 mm off the skin still have it within reach; 60 mm in front of it they float in air.
  const Face lifted(10.0), floating(60.0);
  EXPECT_TRUE(check_landmarks_solid(Ball{}.density(), lifted.cameras, lifted.points, kMmPerUnit).passed);
  const InputCheck air =
      check_landmarks_solid(Ball{}.density(), floating.cameras, floating.points, kMmPerUnit);
  EXPECT_TRUE(air.checked);
  EXPECT_FALSE(air.passed);
  EXPECT_EQ(air.value, 1.0);
  EXPECT_NE(air.reason.find("51 of 51 face landmarks lie in empty space"), std::string::npos) << air.reason;
  // A tunnel 25 mm wide through the nose's band: the nose line (27-35) and nothing else.
  const Face f;
  const InputCheck nose_hole = check_landmarks_solid(Ball{0.0625}.density(), f.cameras, f.points, kMmPerUnit);
  EXPECT_FALSE(nose_hole.passed);
  EXPECT_NE(nose_hole.reason.find("nose bridge"), std::string::npos) << nose_hole.reason;
  EXPECT_NE(nose_hole.reason.find("dlib 27 28"), std::string::npos) << nose_hole.reason;
}

TEST(InputChecks, TempleSpreadWithinWhatAWornFrameBends) {
  TempleFitResult t;
  EXPECT_FALSE(check_temple_spread(t).checked);
  EXPECT_TRUE(check_temple_spread(t).passed);
  t.fitted = true;
  t.left.spread_deg = 8.75, t.right.spread_deg = 3.5;  // the exact meshes' spreads
  EXPECT_TRUE(check_temple_spread(t).passed);
  t.left.spread_deg = 20.0, t.right.spread_deg = 16.5;  // the selfie with holes
  const InputCheck c = check_temple_spread(t);
  EXPECT_FALSE(c.passed);
  EXPECT_EQ(c.value, 20.0);
  EXPECT_EQ(c.limit, kMaxWornSpreadDeg);
  EXPECT_NE(c.reason.find("20.00 / 16.50 deg"), std::string::npos) << c.reason;
  EXPECT_NE(c.reason.find("haze beside the head"), std::string::npos) << c.reason;
  // Turned onto Eq. 2-3's ears, the reason names the ear a temple may pass through.
  const InputCheck estimated = check_temple_spread(t, true);
  EXPECT_FALSE(estimated.passed);
  EXPECT_NE(estimated.reason.find("passes through the ear itself"), std::string::npos) << estimated.reason;
}

TEST(InputChecks, FrontWithinItsToleranceIsNotFailed) {
  // The seated capture: placed well, its front 1.25 mm into the face.
  const InputCheck seated = check_front_penetration(true, 1.25, kFrontToleranceMm);
  EXPECT_TRUE(seated.checked);
  EXPECT_TRUE(seated.passed);
  const InputCheck deep = check_front_penetration(true, 2.0, kFrontToleranceMm);
  EXPECT_FALSE(deep.passed);
  EXPECT_NE(deep.reason.find("still penetrates the face by 2.00 mm"), std::string::npos);
  EXPECT_FALSE(check_front_penetration(false, 5.0, kFrontToleranceMm).checked);
  EXPECT_EQ(PlaceOptions{}.front_tolerance_mm, kFrontToleranceMm);
}

TEST(InputChecks, ChecksReachPlacementJson) {
  FitResult r;
  r.checks.push_back(check_front_penetration(true, 1.25, kFrontToleranceMm));
  r.checks.push_back(check_nose_skin(constant_colour(0.0f), {{0, 0, 0.5}}, {0, 0, -1}));
  const PlacementFile p = make_placement_file(r, "", "stretch");
  const PlacementFile q = placement_from_json(to_json(p));
  ASSERT_TRUE(q.checks.is_object());
  EXPECT_EQ(q.checks["front_penetration"]["passed"], true);
  EXPECT_EQ(q.checks["front_penetration"]["limit"], kFrontToleranceMm);
  EXPECT_EQ(q.checks["nose_skin"]["passed"], false);
  EXPECT_NE(q.checks["nose_skin"]["reason"].get<std::string>().find("reads no skin"), std::string::npos);
  // A placement without checks (hand-written, or older) reads as none; a malformed one is refused.
  nlohmann::json j = to_json(PlacementFile{});
  EXPECT_FALSE(j.contains("checks"));
  EXPECT_TRUE(placement_from_json(j).checks.is_null());
  j["checks"] = 3;
  EXPECT_THROW(placement_from_json(j), std::runtime_error);
}

}  // namespace
}  // namespace lorgnette::fit
