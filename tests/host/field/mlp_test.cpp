// MLP kernels on a two-layer network (32 -> 64 ReLU -> 16): forward vs a double host reference,
// weight and input gradients vs central finite differences of the double reference forward.
#include "host/field/mlp.h"

#include "field_test_util.h"
#include "host/cl/buffer.h"

using namespace lorgnette;
using namespace lorgnette::field;

namespace {

constexpr uint32_t kN = 500, kStride = 512;

LayerShape shape(uint32_t in, uint32_t out, uint64_t offset) {
  LayerShape L;
  L.in = L.in_pad = in;
  L.out = L.out_pad = out;
  L.offset = offset;
  return L;
}

// Loss of the double reference: sum_{j,i} c[j][i] * y[j][i] with y = L2(relu(L1 x)).
double ref_loss(const LayerShape& L1, const LayerShape& L2, const std::vector<float>& w, const ref::Rows& x,
                const ref::Rows& c) {
  ref::Rows h = ref::layer_forward(L1, w, x, kN, LGN_ACT_RELU);
  ref::Rows y = ref::layer_forward(L2, w, h, kN, LGN_ACT_NONE);
  double L = 0;
  for (size_t e = 0; e < y.size(); ++e) L += c[e] * y[e];
  return L;
}

ref::Rows rows_of(const std::vector<float>& buf, uint32_t rows) {
  ref::Rows r(size_t(rows) * kN);
  for (uint32_t j = 0; j < rows; ++j)
    for (uint32_t i = 0; i < kN; ++i) r[size_t(j) * kN + i] = buf[size_t(j) * kStride + i];
  return r;
}

}  // namespace

TEST(Mlp, ForwardAndBackwardMatchReferenceAndFiniteDifferences) {
  auto& rt = test::runtime();
  const LayerShape L1 = shape(32, 64, 0), L2 = shape(64, 16, 32 * 64);
  std::vector<float> w = test::random_vector(L2.offset + L2.count(), 0.3f, 21);
  std::vector<float> x_host = test::random_vector(32 * kStride, 1.0f, 22);
  std::vector<float> c_host = test::random_vector(16 * kStride, 1.0f, 23);
  for (uint32_t j = 0; j < 16; ++j)  // padded samples carry zero deltas, as in the Field
    for (uint32_t i = kN; i < kStride; ++i) c_host[size_t(j) * kStride + i] = 0.0f;

  Mlp mlp(rt, kStride);
  cl::Buffer<float> W(rt, w), x(rt, x_host), h(rt, 64 * kStride), y(rt, 16 * kStride), dz(rt, c_host);
  cl::Buffer<float> dh(rt, 64 * kStride), dx(rt, 32 * kStride), grads(rt, w.size());
  cl::Buffer<float> partial(rt, mlp.max_grad_chunks() * 64 * 64);
  mlp.forward(L1, W, {&x, 0, &h, 0}, kN, LGN_ACT_RELU);
  mlp.forward(L2, W, {&h, 0, &y, 0}, kN, LGN_ACT_NONE);
  mlp.weight_grad(L2, {&h, 0, &dz, 0}, kN, partial, grads);
  mlp.backward_input(L2, W, {&h, 0, &dz, 0}, kN, dh, 0, 0, true);
  mlp.weight_grad(L1, {&x, 0, &dh, 0}, kN, partial, grads);
  mlp.backward_input(L1, W, {&x, 0, &dh, 0}, kN, dx, 0, 0, false);

  const ref::Rows xr = rows_of(x_host, 32), cr = rows_of(c_host, 16);
  ref::Rows hr = ref::layer_forward(L1, w, xr, kN, LGN_ACT_RELU);
  ref::Rows yr = ref::layer_forward(L2, w, hr, kN, LGN_ACT_NONE);
  // 32 / 64 float products of O(1) values: ~1e-6 relative rounding; 1e-5 + 1e-4 relative.
  test::expect_close(rows_of(y.read(rt), 16), yr, 1e-4, 1e-5, "mlp forward");

  auto g = grads.read(rt);
  auto dxv = rows_of(dx.read(rt), 32);
  std::mt19937 rng(3);
  const double L0 = ref_loss(L1, L2, w, xr, cr);
  (void)L0;
  for (int probe = 0; probe < 24; ++probe) {
    const size_t e = probe % 2 ? rng() % (32 * 64) : L2.offset + rng() % L2.count();
    const double step = 1e-5;  // small: a ReLU kink crossed by the step would bias the difference
    std::vector<float> wp = w, wm = w;
    wp[e] += float(step);
    wm[e] -= float(step);
    const double fd = (ref_loss(L1, L2, wp, xr, cr) - ref_loss(L1, L2, wm, xr, cr)) / (double(wp[e]) - wm[e]);
    // Sums over 500 samples in float (chunked): ~1e-5 relative; a ReLU kink crossed by the
    // +-1e-3 step adds O(1e-3) of one sample's term, hence the absolute part.
    EXPECT_NEAR(g[e], fd, 2e-3 + 1e-3 * std::fabs(fd)) << "weight " << e;
  }
  for (int probe = 0; probe < 16; ++probe) {
    const size_t e = rng() % (32 * kN);
    const double step = 1e-5;  // small: a ReLU kink crossed by the step would bias the difference
    ref::Rows xp = xr, xm = xr;
    xp[e] += step;
    xm[e] -= step;
    const double fd = (ref_loss(L1, L2, w, xp, cr) - ref_loss(L1, L2, w, xm, cr)) / (2 * step);
    // One sample's input gradient: 64 x 16 float terms; 1e-4 absolute.
    EXPECT_NEAR(dxv[e], fd, 1e-4 + 1e-4 * std::fabs(fd)) << "input " << e;
  }
}

TEST(Mlp, GradientChunkingIsFixedPerBatchSize) {
  for (uint32_t n : {1u, 16u, 500u, 4096u, 65536u, 262144u, 1u << 20}) {
    for (auto [target, cap] : {std::pair{kGradChunk, kMaxGradChunks}, std::pair{kGradChunkGpuMin, 1056u}}) {
      GradChunks g = grad_chunks(n, target, cap);
      EXPECT_GE(g.chunk * g.chunks, n) << n;
      EXPECT_LE(g.chunks, cap) << n;
      EXPECT_EQ(g.chunk % 16, 0u) << n;
      GradChunks again = grad_chunks(n, target, cap);
      EXPECT_EQ(again.chunk, g.chunk) << n;
      EXPECT_EQ(again.chunks, g.chunks) << n;
    }
  }
}
