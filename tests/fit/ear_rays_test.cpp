// The ear search's ray field (fit/ear_rays.h): where a vertical ray's opacity from above reaches the
// level in a uniform density (1 - exp(-sigma d), exact under the trapezoid rule), the side's axes, and
// misses.
#include "fit/ear_rays.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lorgnette::fit {
namespace {

// The wearer's left side of a head with y up, z forward; 2 mm per scene unit.
EarRootInputs left_side() { return {{70, -5, 10}, {45, 3, 60}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, +1, 2.0}; }

TEST(EarRays, TheSideFrameMapsMillimetresOntoTheScene) {
  const EarRootInputs in = left_side();
  const EarSideFrame f(in);
  EXPECT_NEAR(f.eye_height_mm, 8.0 * 2.0, 1e-12);  // the eye corner 8 units above the temple
  // 4 mm out, 6 mm forward, 2 mm above the eye corner: (2, 3, 8 + 1) units from the temple.
  EXPECT_LT((f.point(4.0, 6.0, 2.0) - Eigen::Vector3d(72, 4, 13)).norm(), 1e-12);
  EarRootInputs right = in;
  right.side = -1, right.temple.x() = -70;
  EXPECT_LT((EarSideFrame(right).point(4.0, 0.0, -16.0) - Eigen::Vector3d(-72, -5, 10)).norm(), 1e-12);
}

TEST(EarRays, ARayStopsWhereItsOpacityReachesTheLevel) {
  const EarRootInputs in = left_side();
  EarRayOptions o;
  const double sigma = 0.2;  // per scene unit, everywhere
  const DensityFn uniform = [&](const std::vector<Eigen::Vector3f>& p) {
    return std::vector<float>(p.size(), float(sigma));
  };
  const EarRayField f = cast_ear_rays(uniform, in, o, {-10.0, -4.0});
  ASSERT_EQ(f.heights.size(), 2u);
  EXPECT_EQ(f.laterals.size(), size_t((o.inward_mm + o.outward_mm) / o.lateral_step_mm) + 1);
  // From the window's top, -ln(1 - q) / sigma scene units down.
  const double expected = o.above_mm - -std::log(1.0 - o.opacity) / sigma * in.mm_per_unit;
  for (const auto& row : f.heights)
    for (double h : row) EXPECT_NEAR(h, expected, 1e-6);
}

TEST(EarRays, ARayThatMeetsNothingIsAMiss) {
  const DensityFn empty = [](const std::vector<Eigen::Vector3f>& p) {
    return std::vector<float>(p.size(), 0.f);
  };
  const EarRayField f = cast_ear_rays(empty, left_side(), EarRayOptions{}, {0.0});
  for (double h : f.heights.at(0)) EXPECT_TRUE(std::isnan(h));
}

TEST(EarRays, RejectsBadInputsAndAWrongDensity) {
  EarRayOptions o;
  EarRootInputs in = left_side();
  EXPECT_NO_THROW(check_ear_search(in, o));
  o.opacity = 1.0;
  EXPECT_THROW(check_ear_search(in, o), std::invalid_argument);
  o = {}, o.back_mm = o.front_mm = 0.0;
  EXPECT_THROW(check_ear_search(in, o), std::invalid_argument);
  const DensityFn short_answer = [](const std::vector<Eigen::Vector3f>&) {
    return std::vector<float>(1, 0.f);
  };
  EXPECT_THROW(cast_ear_rays(short_answer, in, EarRayOptions{}, {0.0}), std::runtime_error);
}

}  // namespace
}  // namespace lorgnette::fit
