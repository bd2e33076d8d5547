// Adam kernel vs a textbook bias-corrected Adam computed in double on the host, over three steps
// with weight decay applying only to the MLP part.
#include "host/field/adam.h"

#include "field_test_util.h"
#include "host/cl/buffer.h"

using namespace lorgnette;
using namespace lorgnette::field;

TEST(Adam, ThreeStepsMatchHostReference) {
  auto& rt = test::runtime();
  const uint32_t count = 1000, mlp_offset = 600;
  AdamConfig cfg;
  cfg.lr = 1e-2f;
  cfg.eps = 1e-8f;
  cfg.mlp_weight_decay = 0.1f;  // large, so a wrong split of the decay would show
  std::vector<float> p0 = test::random_vector(count, 1.0f, 1);
  cl::Buffer<float> params(rt, p0), grads(rt, count), m(rt, count), v(rt, count);
  m.fill(rt, 0.0f);
  v.fill(rt, 0.0f);
  Adam adam(rt);
  std::vector<double> p(p0.begin(), p0.end()), mr(count, 0.0), vr(count, 0.0);
  for (int t = 1; t <= 3; ++t) {
    std::vector<float> g = test::random_vector(count, 0.5f, 100 + t);
    grads.write(rt, g);
    AdamParams ap = make_adam_params(cfg, t, count, mlp_offset);
    ap.clear_below = t == 3 ? 400 : 0;  // the last step clears the gradients it used below 400
    adam.step(ap, params, grads, m, v);
    const std::vector<float> after = grads.read(rt);
    for (uint32_t i = 0; i < count; ++i)
      ASSERT_EQ(after[i], i < ap.clear_below ? 0.0f : g[i]) << "gradient " << i << " after step " << t;
    for (uint32_t i = 0; i < count; ++i) {
      double gi = g[i] + (i >= mlp_offset ? cfg.mlp_weight_decay * p[i] : 0.0);
      mr[i] = cfg.beta1 * mr[i] + (1 - cfg.beta1) * gi;
      vr[i] = cfg.beta2 * vr[i] + (1 - cfg.beta2) * gi * gi;
      double mh = mr[i] / (1 - std::pow(double(cfg.beta1), t)),
             vh = vr[i] / (1 - std::pow(double(cfg.beta2), t));
      p[i] -= cfg.lr * mh / (std::sqrt(vh) + cfg.eps);
    }
  }
  // Each step moves a parameter by ~lr = 1e-2; float rounding of that update is ~1e-8.
  test::expect_close(params.read(rt), p, 1e-6, 1e-6, "parameters after 3 Adam steps");
  test::expect_close(m.read(rt), mr, 1e-5, 1e-7, "first moments");
}

// Sparse hash updates: below skip_zero_below a zero gradient leaves the parameter and both moments
// exactly as they were (the moments do not decay); every other parameter, including zero-gradient
// ones above the limit, gets the dense update. Three steps against the double reference.
TEST(Adam, SparseUpdateSkipsOnlyZeroGradientsBelowTheLimit) {
  auto& rt = test::runtime();
  const uint32_t count = 1000, mlp_offset = 600, skip_below = 500;
  AdamConfig cfg;
  cfg.eps = 1e-8f;
  cfg.mlp_weight_decay = 0.1f;
  std::vector<float> p0 = test::random_vector(count, 1.0f, 2);
  cl::Buffer<float> params(rt, p0), grads(rt, count), m(rt, count), v(rt, count);
  m.fill(rt, 0.0f);
  v.fill(rt, 0.0f);
  Adam adam(rt);
  std::vector<double> p(p0.begin(), p0.end()), mr(count, 0.0), vr(count, 0.0);
  uint32_t skipped = 0;
  for (int t = 1; t <= 3; ++t) {
    std::vector<float> g = test::random_vector(count, 0.5f, 200 + t);
    for (uint32_t i = 0; i < count; ++i)
      if ((i * 7 + t * 3) % 5 < 2) g[i] = 0.0f;  // 40 % zeros, a different set each step
    grads.write(rt, g);
    AdamParams ap = make_adam_params(cfg, t, count, mlp_offset);
    ap.clear_below = skip_below;
    ap.skip_zero_below = skip_below;
    const std::vector<float> before = params.read(rt);
    adam.step(ap, params, grads, m, v);
    const std::vector<float> after = params.read(rt), g_after = grads.read(rt);
    for (uint32_t i = 0; i < count; ++i) {
      ASSERT_EQ(g_after[i], i < skip_below ? 0.0f : g[i]) << "gradient " << i;
      if (i < skip_below && g[i] == 0.0f) {
        ASSERT_EQ(after[i], before[i]) << "skipped parameter " << i << " moved at step " << t;
        ++skipped;
        continue;
      }
      double gi = g[i] + (i >= mlp_offset ? cfg.mlp_weight_decay * p[i] : 0.0);
      mr[i] = cfg.beta1 * mr[i] + (1 - cfg.beta1) * gi;
      vr[i] = cfg.beta2 * vr[i] + (1 - cfg.beta2) * gi * gi;
      double mh = mr[i] / (1 - std::pow(double(cfg.beta1), t)),
             vh = vr[i] / (1 - std::pow(double(cfg.beta2), t));
      p[i] -= cfg.lr * mh / (std::sqrt(vh) + cfg.eps);
    }
  }
  EXPECT_GT(skipped, 500u);
  test::expect_close(params.read(rt), p, 1e-6, 1e-6, "parameters after 3 sparse Adam steps");
  test::expect_close(m.read(rt), mr, 1e-5, 1e-7, "first moments (skipped ones unchanged)");
  test::expect_close(v.read(rt), vr, 1e-5, 1e-9, "second moments (skipped ones unchanged)");
}

TEST(Adam, InvalidConfigurationIsAClearError) {
  AdamConfig cfg;
  cfg.beta2 = 1.0f;
  EXPECT_THROW(make_adam_params(cfg, 1, 10, 5), std::invalid_argument);
}
