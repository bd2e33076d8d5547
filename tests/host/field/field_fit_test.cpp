// Regression: Adam fits the Field to an analytic density (a Gaussian blob) and a colour that
// depends on position and view direction; the loss must drop by a stated factor.
#include "field_test_util.h"
#include "host/cl/buffer.h"
#include "host/field/field.h"

using namespace lorgnette;
using namespace lorgnette::field;

namespace {

struct Target {
  static double sigma(double x, double y, double z) {
    const double r2 = (x - 0.5) * (x - 0.5) + (y - 0.4) * (y - 0.4) + (z - 0.6) * (z - 0.6);
    return 30.0 * std::exp(-r2 / 0.03);
  }
  static double rgb(int c, double x, double y, double z, double dz) {
    if (c == 0) return 0.2 + 0.6 * x;
    if (c == 1) return 0.5 + 0.3 * std::sin(6.0 * y);
    return 0.5 + 0.3 * dz * z;
  }
};

}  // namespace

TEST(FieldFit, AdamReducesTheLossOfAnAnalyticFieldTenfold) {
  auto& rt = test::runtime();
  FieldConfig cfg;
  cfg.levels = 8;
  cfg.log2_table_size = 14;
  cfg.base_resolution = 4;
  cfg.finest_resolution = 128;
  const uint32_t n = 4096;
  Field field(rt, cfg, n, 1, true);
  const size_t S = field.max_batch();
  cl::Buffer<float> pos(rt, 3 * S), dir(rt, 3 * S), sigma(rt, S), rgb(rt, 3 * S), dsig(rt, S),
      drgb(rt, 3 * S);
  AdamConfig adam;
  std::vector<double> losses;
  for (int step = 0; step < 200; ++step) {
    ref::Samples s = test::random_samples(n, uint32_t(S), 1000 + step);
    pos.write(rt, s.pos);
    dir.write(rt, s.dir);
    field.forward(pos, dir, n, sigma, rgb, true);
    auto sg = sigma.read(rt, n);
    auto c = rgb.read(rt);
    std::vector<float> gs(S, 0.0f), gc(3 * S, 0.0f);
    double L = 0;
    for (uint32_t i = 0; i < n; ++i) {
      const double x = s.pos[i], y = s.pos[S + i], z = s.pos[2 * S + i];
      // Density in log space (log1p), as sigma spans orders of magnitude.
      const double e = std::log1p(double(sg[i])) - std::log1p(Target::sigma(x, y, z));
      L += e * e / n;
      gs[i] = float(2.0 * e / (1.0 + sg[i]) / n);
      for (int k = 0; k < 3; ++k) {
        const double d = c[k * S + i] - Target::rgb(k, x, y, z, s.dir[2 * S + i]);
        L += d * d / n;
        gc[k * S + i] = float(2.0 * d / n);
      }
    }
    losses.push_back(L);
    dsig.write(rt, gs);
    drgb.write(rt, gc);
    field.backward(dsig, drgb, n);
    field.adam_step(adam);
  }
  double first = 0, last = 0;
  for (int k = 0; k < 10; ++k) {
    first += losses[k] / 10;
    last += losses[losses.size() - 1 - k] / 10;
  }
  // Measured about 30x on PoCL; a factor 10 catches broken gradients or Adam without being tight.
  EXPECT_LT(last, first / 10) << "loss went from " << first << " to " << last;
  RecordProperty("loss_first", std::to_string(first));
  RecordProperty("loss_last", std::to_string(last));
  std::printf("fit loss: first 10 steps %.5f, last 10 steps %.5f (x%.1f)\n", first, last, first / last);
}
