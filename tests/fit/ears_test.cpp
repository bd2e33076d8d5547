// Eq. 2-3 on a hand-made configuration with an exact answer, and its invariance to the length of d_up.
#include "fit/ears.h"

#include <gtest/gtest.h>

namespace lorgnette::fit {
namespace {

TEST(Ears, EquationTwoAndThreeExact) {
  EarInputs in;
  in.e_l = {45, 0, 5};
  in.e_r = {-45, 0, 5};  // |e_l - e_r| = 90
  in.t_l = {70, -8, -40};
  in.t_r = {-71, 6, -42};
  in.d_up = {0, 1, 0};
  in.d_fwd = {0, 0, 1};
  EarPoints e = ear_points(in, 0.5);
  // Eq. 2: temples moved to the eye height (y = 0); Eq. 3: 0.5 * 90 = 45 mm back.
  EXPECT_LT((e.t_hat_l - Eigen::Vector3d(70, 0, -40)).norm(), 1e-12);
  EXPECT_LT((e.t_hat_r - Eigen::Vector3d(-71, 0, -42)).norm(), 1e-12);
  EXPECT_LT((e.f_l - Eigen::Vector3d(70, 0, -85)).norm(), 1e-12);
  EXPECT_LT((e.f_r - Eigen::Vector3d(-71, 0, -87)).norm(), 1e-12);
  in.d_up *= 3.0;  // Eq. 2's first form divides by d_up . d_up
  EXPECT_LT((ear_points(in, 0.5).t_hat_l - e.t_hat_l).norm(), 1e-12);
  EXPECT_LT((ear_points(in, 0.0).f_l - e.t_hat_l).norm(), 1e-12);
}

TEST(Ears, NosePointBlend) {
  EXPECT_LT((nose_point({0, 10, 0}, {0, 0, 4}, 0.25) - Eigen::Vector3d(0, 7.5, 1)).norm(), 1e-12);
}

}  // namespace
}  // namespace lorgnette::fit
