// PD from limbus centres (fit/pupil_distance.h) on synthetic measurements with known centres: the
// distance between the eyes' mean centres, the per-eye sigma (the spread's standard error along the
// eyes' line, floored at a share of the iris), and the refusal when an eye has no limbus.
#include "fit/pupil_distance.h"

#include <gtest/gtest.h>

namespace lorgnette::fit {
namespace {

IrisMeasurement at(int eye, const Eigen::Vector3d& centre, double iris_units = 0.06, bool found = true) {
  IrisMeasurement m;
  m.eye = eye;
  m.edges.found = found;
  m.diameter_units = iris_units;
  m.centre = centre;
  return m;
}

// Left eye's views at x = 0.30 +- 0.01, right's at -0.32 (exact): PD 0.62; the left's spread along x
// is 0.01 (SD over 3), so its standard error 0.01 / sqrt(3); the right's is floored at 5 % of 0.06.
// A spread in depth (z) is not along the eyes' line and does not count.
TEST(PupilDistance, MeanCentresAndTheirSigma) {
  const std::vector<IrisMeasurement> ms = {
      at(+1, {0.29, 0.0, 0.0}),
      at(+1, {0.30, 0.0, 0.05}),
      at(+1, {0.31, 0.0, -0.05}),
      at(-1, {-0.32, 0.0, 0.0}),
      at(-1, {-0.32, 0.0, 0.02}),
      at(-1, {-0.32, 0.0, -0.02}),
      at(-1, {5.0, 5.0, 5.0}, 0.06, false)};  // a view whose limbus was not found: ignored
  const PupilDistance p = pupil_distance(ms);
  ASSERT_TRUE(p.ok) << p.why;
  EXPECT_NEAR(p.units, 0.62, 1e-9);
  EXPECT_NEAR(p.sigma_left, 0.01 / std::sqrt(3.0), 1e-9);
  EXPECT_NEAR(p.sigma_right, 0.05 * 0.06, 1e-12);
  EXPECT_NEAR(p.left.x(), 0.30, 1e-12);
  EXPECT_NEAR(p.right.x(), -0.32, 1e-12);
}

TEST(PupilDistance, RefusedWithoutBothEyes) {
  PupilDistance p = pupil_distance({at(+1, {0.3, 0, 0}), at(-1, {-0.3, 0, 0}, 0.06, false)});
  EXPECT_FALSE(p.ok);
  EXPECT_NE(p.why.find("right"), std::string::npos) << p.why;
  p = pupil_distance({at(-1, {-0.3, 0, 0})});
  EXPECT_FALSE(p.ok);
  EXPECT_NE(p.why.find("left"), std::string::npos) << p.why;
  EXPECT_FALSE(pupil_distance({}).ok);
  // An eye closed in every view: said so with the views' reason (the lens height then says it too).
  IrisMeasurement shut = at(+1, {0.3, 0, 0}, 0.06, false);
  shut.closed = true;
  shut.edges.why = "lid opening 0.167 of the eye's width < 0.18";
  p = pupil_distance({shut, shut, at(-1, {-0.3, 0, 0})});
  EXPECT_FALSE(p.ok);
  EXPECT_EQ(p.why, "the left eye is closed (lid opening 0.167 of the eye's width < 0.18)");
}

}  // namespace
}  // namespace lorgnette::fit
