// Shared helpers of the field tests: one OpenCL runtime per process, seeded random samples, the
// small configurations the tests use, and a closeness check that reports the worst element.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "field_reference.h"
#include "host/cl/runtime.h"
#include "host/field/field_config.h"

namespace lorgnette::field::test {

inline cl::Runtime& runtime() {
  static cl::Runtime rt;  // device: default rule (PoCL here); cache: $LORGNETTE_KERNEL_CACHE
  return rt;
}

// 4 levels (resolutions 4, 10, 25, 64): a dense level and hashed ones with collisions (2^10).
inline FieldConfig small_config() {
  FieldConfig c;
  c.levels = 4;
  c.log2_table_size = 10;
  c.base_resolution = 4;
  c.finest_resolution = 64;
  return c;
}

// Widths that are not multiples of 4 (padding paths) and SH degree 3.
inline FieldConfig odd_config() {
  FieldConfig c = small_config();
  c.levels = 3;
  c.density_hidden = 30;
  c.geo_features = 15;
  c.color_hidden = 22;
  c.color_hidden_layers = 1;
  c.sh_degree = 3;
  return c;
}

inline ref::Samples random_samples(uint32_t n, uint32_t stride, uint64_t seed) {
  std::mt19937 rng{uint32_t(seed)};
  std::uniform_real_distribution<float> u(0.0f, 1.0f), g(-1.0f, 1.0f);
  ref::Samples s;
  s.n = n;
  s.stride = stride;
  s.pos.assign(3 * size_t(stride), 0.0f);
  s.dir.assign(3 * size_t(stride), 0.0f);
  for (uint32_t i = 0; i < n; ++i) {
    float d[3];
    float len = 0;
    do {
      for (float& x : d) x = g(rng);
      len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    } while (len < 0.1f || len > 1.0f);
    for (int a = 0; a < 3; ++a) {
      s.pos[a * size_t(stride) + i] = u(rng);
      s.dir[a * size_t(stride) + i] = d[a] / len;
    }
  }
  return s;
}

inline std::vector<float> random_vector(size_t count, float amplitude, uint64_t seed) {
  std::mt19937 rng{uint32_t(seed)};
  std::uniform_real_distribution<float> u(-amplitude, amplitude);
  std::vector<float> v(count);
  for (float& x : v) x = u(rng);
  return v;
}

// |got - want| <= atol + rtol * |want| for every element; reports the worst one.
template <class A, class B>
void expect_close(const A& got, const B& want, double rtol, double atol, const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  double worst = 0;
  size_t at = 0;
  for (size_t e = 0; e < got.size(); ++e) {
    const double err =
        std::fabs(double(got[e]) - double(want[e])) / (atol + rtol * std::fabs(double(want[e])));
    if (!(err <= worst)) {
      worst = err;
      at = e;
    }
  }
  EXPECT_LE(worst, 1.0) << what << ": element " << at << " is " << got[at] << ", expected " << want[at]
                        << " (rtol " << rtol << ", atol " << atol << ")";
}

inline double max_abs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::fabs(x));
  return m;
}

}  // namespace lorgnette::field::test
