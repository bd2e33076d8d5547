// Disney BRDF tests: white furnace (directional albedo <= 1 on a roughness x metallic x specular x
// view-angle grid, by Monte Carlo with multiple importance sampling and a stated error bound),
// reciprocity f(l, v) = f(v, l), the Lambert limit, and Fresnel sanity.
#include "mesh/disney_brdf.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

namespace lorgnette::mesh {
namespace {

// Directional albedo for view v (in the frame n = +z) with N samples, half cosine-weighted, half
// from the GGX normal distribution, weighted by the one-sample mixture pdf (balance heuristic).
// Returns mean and standard error of the green channel (base colour is white, all channels equal).
std::pair<double, double> albedo(const BrdfParams& p, float cos_v, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  const Eigen::Vector3f nrm(0, 0, 1), v(std::sqrt(1 - cos_v * cos_v), 0, cos_v);
  const float alpha = disney_alpha(p.roughness);
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i) {
    float a = u01(rng), b = u01(rng);
    Eigen::Vector3f l;
    if (i % 2 == 0) {  // cosine-weighted
      float r = std::sqrt(a), phi = 2 * kPi * b;
      l = {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1 - a))};
    } else {  // GGX half vector, reflected
      float t2 = alpha * alpha * a / std::max(1e-12f, 1 - a), ct = 1 / std::sqrt(1 + t2),
            st = std::sqrt(1 - ct * ct);
      Eigen::Vector3f h(st * std::cos(2 * kPi * b), st * std::sin(2 * kPi * b), ct);
      l = 2 * v.dot(h) * h - v;
    }
    double value = 0;
    if (l.z() > 0) {
      Eigen::Vector3f h = (l + v).normalized();
      double pdf_cos = l.z() / kPi;
      double pdf_ggx = ggx_d(h.z(), alpha) * h.z() / (4 * std::max(1e-7f, v.dot(h)));
      value = disney_brdf(p, nrm, l, v).y() * l.z() / (0.5 * pdf_cos + 0.5 * pdf_ggx);
    }
    sum += value, sum2 += value * value;
  }
  double mean = sum / n, var = sum2 / n - mean * mean;
  return {mean, std::sqrt(std::max(0.0, var) / n)};
}

TEST(DisneyBrdf, WhiteFurnaceAlbedoAtMostOne) {
  const int n = 40000;
  double worst = 0;
  for (float rough : {0.05f, 0.2f, 0.4f, 0.6f, 0.8f, 1.0f})
    for (float metal : {0.0f, 0.5f, 1.0f})
      for (float spec : {0.0f, 0.5f, 1.0f})
        for (float cos_v : {1.0f, 0.7f, 0.4f, 0.15f, 0.05f}) {
          BrdfParams p{Eigen::Vector3f::Ones(), metal, rough, spec};
          auto [a, se] = albedo(p, cos_v, n, 17u);
          worst = std::max(worst, a);
          // 4 standard errors: a false failure has probability ~3e-5 per grid point (810 points);
          // 0.01 absolute covers the GGX sampler's pdf floor at the grazing end.
          EXPECT_LE(a, 1.0 + 4 * se + 0.01) << "roughness " << rough << " metallic " << metal << " specular "
                                            << spec << " cos_v " << cos_v << " (se " << se << ")";
        }
  std::printf("largest white-furnace albedo on the grid: %.4f\n", worst);
}

TEST(DisneyBrdf, Reciprocity) {
  std::mt19937 rng(5);
  std::normal_distribution<float> g;
  const Eigen::Vector3f n(0, 0, 1);
  for (int i = 0; i < 2000; ++i) {
    Eigen::Vector3f l(g(rng), g(rng), std::abs(g(rng)) + 0.05f), v(g(rng), g(rng), std::abs(g(rng)) + 0.05f);
    l.normalize(), v.normalize();
    BrdfParams p{Eigen::Vector3f(0.7f, 0.4f, 0.2f), (i % 5) / 4.0f, 0.05f + (i % 7) / 7.0f, (i % 3) / 2.0f};
    Eigen::Vector3f a = disney_brdf(p, n, l, v), b = disney_brdf(p, n, v, l);
    // Same arithmetic with the roles swapped: float rounding only (1e-5 relative + 1e-7 absolute).
    EXPECT_LE((a - b).norm(), 1e-5f * a.norm() + 1e-7f) << i;
  }
}

TEST(DisneyBrdf, LambertLimit) {
  const Eigen::Vector3f n(0, 0, 1), base(0.6f, 0.3f, 0.1f);
  BrdfParams p{base, 0.0f, 0.0f, 0.0f};
  // Normal incidence, roughness 0, no specular: every Fresnel weight is 0; the GGX spike is
  // multiplied by F0 = 0, so f = base / pi exactly (1e-6: float rounding).
  EXPECT_LE((disney_brdf(p, n, n, n) - lambert_brdf(base)).norm(), 1e-6f);
  // Albedo at normal incidence, roughness 0, specular 0: the diffuse factor reduces to
  // (1 - (1 - cos_l)^5)^2 (Burley grazing darkening x Fresnel coupling), whose cosine-weighted
  // integral is 1 - 4 B(2,6) + 2 B(2,11) = 1 - 4/42 + 2/132 = 0.919913 (Lambert: 1). 4 standard
  // errors + 0.002 for the specular spike's residue at alpha = 0.0004.
  BrdfParams white{Eigen::Vector3f::Ones(), 0.0f, 0.0f, 0.0f};
  auto [a, se] = albedo(white, 1.0f, 200000, 3u);
  EXPECT_NEAR(a, 0.919913, 4 * se + 0.002) << "se " << se;
}

TEST(DisneyBrdf, FresnelDielectric) {
  // Normal incidence: ((n - 1) / (n + 1))^2 = 0.04 for n = 1.5; total reflection at grazing.
  EXPECT_NEAR(fresnel_dielectric(1.0f, 1.5f), 0.04f, 1e-6f);
  EXPECT_NEAR(fresnel_dielectric(0.0f, 1.5f), 1.0f, 1e-6f);
  EXPECT_LT(fresnel_dielectric(0.7f, 1.5f), 0.06f);
}

}  // namespace
}  // namespace lorgnette::mesh
