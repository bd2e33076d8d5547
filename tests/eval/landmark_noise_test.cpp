// The studies' detector noise (eval/landmark_noise.h) on a detector that always answers the same 68
// points: the added offsets have the stated spread and no bias, the boxes stay, and one seed draws
// the same noise call by call.
#include "eval/landmark_noise.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lorgnette::fit {
namespace {

FaceDetection fixed(const std::vector<unsigned char>&, int, int, double) {
  FaceDetection d;
  d.found = true, d.box = {10, 20, 110, 140};
  for (int k = 0; k < 68; ++k) d.points.emplace_back(k, 2.0 * k);
  return d;
}

TEST(LandmarkNoise, AddsUnbiasedNoiseOfTheStatedSpread) {
  const double sigma = 2.0;
  DetectFn noisy = with_landmark_noise(fixed, sigma, 7);
  const FaceDetection truth = fixed({}, 0, 0, 0.0);
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  for (int call = 0; call < 200; ++call) {
    const FaceDetection d = noisy({}, 64, 64, 0.0);
    EXPECT_EQ(d.box, truth.box);
    for (size_t k = 0; k < d.points.size(); ++k)
      for (int a = 0; a < 2; ++a) {
        const double e = d.points[k][a] - truth.points[k][a];
        sum += e, sum2 += e * e, ++n;
      }
  }
  // 27,200 draws: the mean within 4 standard errors (0.05 px), the spread within 2 %.
  EXPECT_NEAR(sum / n, 0.0, 4.0 * sigma / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(sum2 / n), sigma, 0.02 * sigma);
}

TEST(LandmarkNoise, OneSeedDrawsTheSameNoiseInCallOrder) {
  DetectFn a = with_landmark_noise(fixed, 1.5, 3), b = with_landmark_noise(fixed, 1.5, 3),
           c = with_landmark_noise(fixed, 1.5, 4);
  for (int call = 0; call < 3; ++call) {
    const FaceDetection da = a({}, 64, 64, 0.0), db = b({}, 64, 64, 0.0), dc = c({}, 64, 64, 0.0);
    EXPECT_EQ(da.points, db.points);
    EXPECT_NE(da.points, dc.points);
  }
}

}  // namespace
}  // namespace lorgnette::fit
