// The placement transform: translate/rotate/scale and 4x4 text (moved here from the render job's
// test with their code), the checks every reader and writer applies, and the one rough placement
// (the render bench's box-aligned form and the viewer's orbit-aligned form) on boxes with known
// answers.
#include "fit/placement_transform.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "host/util/bounds.h"
#include "tests/common/range_error.h"

namespace lorgnette::fit {
namespace {

using lorgnette::testing::range_error;

TEST(PlacementTransform, HandPlacementsAreFiniteAndInRange) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_HAS(range_error([&] {
               trs_transform({nan, 0, 0}, {0, 0, 0}, 1.0f);
             }),
             "--translate (Python: translate)");
  EXPECT_HAS(range_error([&] {
               trs_transform({0, 0, 0}, {0, 1e9f, 0}, 1.0f);
             }),
             "--rotate (Python: rotate_deg)");
  EXPECT_HAS(range_error([&] { trs_transform({0, 0, 0}, {0, 0, 0}, -1.0f); }), "--scale (Python: scale)");
  EXPECT_HAS(range_error([&] { trs_transform({0, 0, 0}, {0, 0, 0}, 1e30f); }), "--scale");
  EXPECT_EQ(trs_transform({1, 2, 3}, {0, 0, 0}, 0.5f)(0, 3), 1.0);
}

TEST(PlacementTransform, TrsRotatesScalesThenTranslates) {
  Transform m = trs_transform({1, 2, 3}, {0, 0, 90}, 2.0f);
  // (1, 0, 0) -> scaled (2, 0, 0) -> rotated 90 deg about z (0, 2, 0) -> translated (1, 4, 3).
  Eigen::Vector4d q = m * Eigen::Vector4d(1, 0, 0, 1);
  EXPECT_NEAR((q.head<3>() - Eigen::Vector3d(1, 4, 3)).norm(), 0.0, 1e-12);
  // R = Rz * Ry * Rx: x first. (0, 1, 0) about x by 90 -> (0, 0, 1), then about y by 90 -> (1, 0, 0).
  Eigen::Vector4d r = trs_transform({0, 0, 0}, {90, 90, 0}, 1.0f) * Eigen::Vector4d(0, 1, 0, 1);
  EXPECT_NEAR((r.head<3>() - Eigen::Vector3d(1, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_THROW(trs_transform({0, 0, 0}, {0, 0, 0}, 0.0f), std::invalid_argument);
  EXPECT_THROW(trs_transform({0, 0, 0}, {0, 0, 0}, NAN), std::invalid_argument);
}

TEST(PlacementTransform, ParsesTextAndRefusesBadMatrices) {
  Transform m = parse_transform("[[1,0,0,5],[0,1,0,6],[0,0,1,7],[0,0,0,1]]");
  EXPECT_EQ(m(0, 3), 5.0);
  EXPECT_EQ(m(2, 3), 7.0);
  EXPECT_THROW(parse_transform("1 2 3"), std::invalid_argument);
  EXPECT_THROW(parse_transform("1 0 0 0 0 1 0 0 0 0 1 0 0 0 1 1"), std::invalid_argument);  // not affine
  EXPECT_THROW(parse_transform("1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 x"), std::invalid_argument);
  EXPECT_THROW(parse_transform("0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 1"), std::invalid_argument);  // all zero
  EXPECT_THROW(parse_transform("1e300 0 0 0 0 1e300 0 0 0 0 1e300 0 0 0 0 1"), std::invalid_argument);
  try {
    parse_transform("1 0 0 0 0 1 0 0 1 0 0 0 0 0 0 1", "--transform");  // x and z the same axis
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--transform"), std::string::npos);
  }
}

TEST(PlacementTransform, ChecksScaleBoundsPerAxis) {
  Transform m = Transform::Identity();
  m.block<3, 3>(0, 0) *= kMaxTransformScale;
  EXPECT_NO_THROW(check_transform(m, "m"));
  m(0, 0) *= 2.0;
  EXPECT_THROW(check_transform(m, "m"), std::invalid_argument);
  m = Transform::Identity();
  m(1, 1) = kMinTransformScale / 2;
  EXPECT_THROW(check_transform(m, "m"), std::invalid_argument);
  m = Transform::Identity();
  m(2, 3) = 2 * kMaxTranslation;
  EXPECT_THROW(check_transform(m, "m"), std::invalid_argument);
}

// A box 2 units wide, 1 high and 0.5 deep around (1, 2, 3); a 100 mm frame: 80 % of 2 units over
// 100 mm = 0.016 units/mm; the bridge centred in x, at 60 % of the height, 12 % inside the front.
TEST(PlacementTransform, RoughPlacementOnTheBoxFront) {
  Eigen::Vector3d lo(0, 1.5, 2.75), hi(2, 2.5, 3.25);
  Transform m = rough_placement(100.0, lo, hi);
  EXPECT_NEAR((m.block<3, 3>(0, 0) - 0.016 * Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-15);
  EXPECT_NEAR((m.block<3, 1>(0, 3) - Eigen::Vector3d(1.0, 2.1, 3.19)).norm(), 0.0, 1e-12);
  EXPECT_NO_THROW(check_transform(m, "rough"));
  // The same head turned 90 degrees about y (its front along +x): the same rule in its own axes.
  Eigen::Matrix3d turn = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  HeadAxes axes;
  axes.x = turn * Eigen::Vector3d::UnitX();
  axes.up = turn * Eigen::Vector3d::UnitY();
  axes.front = turn * Eigen::Vector3d::UnitZ();
  axes.center = Eigen::Vector3d(1, 2, 3);
  Eigen::Vector3d c = axes.center;
  // The turned box: extents 2 along axes.x, 1 along up, 0.5 along front, as above.
  Eigen::Vector3d half(1.0, 0.5, 0.25), tlo = c, thi = c;
  for (int k = 0; k < 8; ++k) {
    Eigen::Vector3d p = c + turn * Eigen::Vector3d(k & 1 ? half.x() : -half.x(), k & 2 ? half.y() : -half.y(),
                                                   k & 4 ? half.z() : -half.z());
    tlo = tlo.cwiseMin(p), thi = thi.cwiseMax(p);
  }
  Transform t = rough_placement(100.0, tlo, thi, axes);
  Eigen::Matrix4d turn4 = Eigen::Matrix4d::Identity();
  turn4.block<3, 3>(0, 0) = turn;
  Eigen::Matrix4d about_c = Eigen::Matrix4d::Identity();
  about_c.block<3, 1>(0, 3) = c;
  Eigen::Matrix4d expected = about_c * turn4 * about_c.inverse() * m;
  EXPECT_NEAR((t - expected).norm(), 0.0, 1e-12);
  // A degenerate width counts as 1 mm instead of dividing by zero.
  EXPECT_TRUE(rough_placement(0.0, lo, hi).allFinite());
}

}  // namespace
}  // namespace lorgnette::fit
