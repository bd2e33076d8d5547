// Hash encoding kernels vs the host reference (forward and backward) and the backward vs finite
// differences of the forward kernel. Tables are random in [-1, 1] so every term matters.
#include "host/field/hashgrid.h"

#include <random>

#include "field_test_util.h"
#include "host/cl/buffer.h"

using namespace lorgnette;
using namespace lorgnette::field;

namespace {

struct HashSetup {
  FieldConfig cfg = test::small_config();
  ParamLayout lay = make_layout(cfg);
  uint32_t n = 1000, stride = 1024;
  ref::Samples s = test::random_samples(n, stride, 7);
  std::vector<float> params = test::random_vector(lay.total, 1.0f, 11);
};

}  // namespace

namespace lorgnette::field {
void PrintTo(KernelVariant v, std::ostream* os) {
  *os << (v == KernelVariant::Gpu ? "gpu variant" : "cpu variant");
}
}  // namespace lorgnette::field

class HashGridVariants : public ::testing::TestWithParam<KernelVariant> {};
INSTANTIATE_TEST_SUITE_P(Kernels, HashGridVariants, ::testing::Values(KernelVariant::Cpu, KernelVariant::Gpu),
                         [](const auto& info) { return info.param == KernelVariant::Gpu ? "Gpu" : "Cpu"; });

// Both kernel variants run on PoCL: the GPU one (scalar, one work-item per sample and level) is
// forced by build options so it is tested without a GPU.
TEST_P(HashGridVariants, EncodeMatchesHostReference) {
  auto& rt = test::runtime();
  HashSetup h;
  HashGrid grid(rt, h.cfg, h.lay, h.stride, GetParam());
  cl::Buffer<float> params(rt, h.params), pos(rt, h.s.pos), enc(rt, size_t(h.lay.enc_pad) * h.stride);
  enc.fill(rt, -7.0f);
  grid.encode(params, pos, h.n, enc);
  auto got = enc.read(rt);
  ref::Rows want = ref::encode(h.lay, h.cfg, h.params, h.s);
  std::vector<float> got_rows;
  for (uint32_t r = 0; r < h.lay.enc_width; ++r)
    got_rows.insert(got_rows.end(), got.begin() + size_t(r) * h.stride,
                    got.begin() + size_t(r) * h.stride + h.n);
  want.resize(size_t(h.lay.enc_width) * h.n);
  // 8 float products of magnitude <= 1 summed: float rounding ~1e-6; 1e-5 leaves margin.
  test::expect_close(got_rows, want, 1e-5, 1e-5, "encoding");
  // Samples n..n16 are zeroed so the MLP's 16-wide vectors never read garbage.
  for (uint32_t i = h.n; i < 1008; ++i) EXPECT_EQ(got[i], 0.0f) << i;
}

TEST_P(HashGridVariants, BackwardMatchesReferenceAndFiniteDifferences) {
  auto& rt = test::runtime();
  HashSetup h;
  HashGrid grid(rt, h.cfg, h.lay, h.stride, GetParam());
  std::vector<float> d_enc_host = test::random_vector(size_t(h.lay.enc_pad) * h.stride, 1.0f, 5);
  cl::Buffer<float> params(rt, h.params), pos(rt, h.s.pos), d_enc(rt, d_enc_host);
  cl::Buffer<float> grads(rt, h.lay.total), enc(rt, size_t(h.lay.enc_pad) * h.stride);
  grads.fill(rt, 3.0f);  // the hash part must be overwritten
  grid.backward(pos, d_enc, h.n, grads, true);
  auto got = grads.read(rt, h.lay.hash_count);

  ref::Rows d_rows(size_t(h.lay.enc_width) * h.n);
  for (uint32_t r = 0; r < h.lay.enc_width; ++r)
    for (uint32_t i = 0; i < h.n; ++i) d_rows[size_t(r) * h.n + i] = d_enc_host[size_t(r) * h.stride + i];
  auto want = ref::encode_backward(h.lay, h.cfg, h.s, d_rows);
  want.resize(h.lay.hash_count);
  // Up to ~100 float terms of magnitude <= 1 per dense entry: 1e-5 relative of the largest.
  test::expect_close(got, want, 1e-4, 1e-5 * test::max_abs(want), "hash gradient vs reference");

  // L = sum d_enc * enc is linear in the table: central differences are exact up to rounding.
  auto loss = [&](const std::vector<float>& p) {
    cl::Buffer<float> pb(rt, p);
    grid.encode(pb, pos, h.n, enc);
    auto e = enc.read(rt);
    double L = 0;
    for (uint32_t r = 0; r < h.lay.enc_width; ++r)
      for (uint32_t i = 0; i < h.n; ++i)
        L += double(e[size_t(r) * h.stride + i]) * d_enc_host[size_t(r) * h.stride + i];
    return L;
  };
  std::vector<size_t> probes;
  for (size_t e = 0; e < h.lay.hash_count && probes.size() < 6; e += 97)
    if (std::fabs(want[e]) > 0.05 * test::max_abs(want)) probes.push_back(e);
  ASSERT_GE(probes.size(), 3u);
  for (size_t e : probes) {
    std::vector<float> p = h.params;
    const float step = 0.25f;
    p[e] = h.params[e] + step;
    double Lp = loss(p);
    p[e] = h.params[e] - step;
    double Lm = loss(p);
    const double fd = (Lp - Lm) / (2.0 * step);
    // Loss sums ~8000 float terms (~1e-3 absolute rounding) divided by 0.5.
    EXPECT_NEAR(got[e], fd, 5e-3 + 1e-3 * std::fabs(fd)) << "entry " << e;
  }
}

// Samples as a ray sampler writes them: consecutive points a small step apart along rays, so on the
// coarse levels long runs of samples add into the same entries one after the other (the case of a
// training batch, which random positions never produce). Against the reference for 2 and 8
// features per level, on both variants.
TEST_P(HashGridVariants, BackwardOfSamplesAlongRaysMatchesReference) {
  auto& rt = test::runtime();
  for (uint32_t features : {2u, 8u}) {
    FieldConfig cfg = test::small_config();
    cfg.features_per_level = features;
    const ParamLayout lay = make_layout(cfg);
    const uint32_t rays = 40, per_ray = 25, n = rays * per_ray, stride = 1024;
    ref::Samples s = test::random_samples(n, stride, 9);
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u(0.1f, 0.9f);
    uint32_t same_cell = 0;  // consecutive samples in one cell of the coarsest level (resolution 4)
    for (uint32_t r = 0; r < rays; ++r) {
      const float o[3] = {u(rng), u(rng), u(rng)};
      for (uint32_t k = 0; k < per_ray; ++k) {
        const uint32_t i = r * per_ray + k;
        for (int a = 0; a < 3; ++a)
          s.pos[a * size_t(stride) + i] = o[a] + 0.004f * float(k) * s.dir[a * size_t(stride) + r * per_ray];
        if (k > 0) {
          bool same = true;
          for (int a = 0; a < 3; ++a)
            same = same && std::floor(4.0f * s.pos[a * size_t(stride) + i]) ==
                               std::floor(4.0f * s.pos[a * size_t(stride) + i - 1]);
          same_cell += same;
        }
      }
    }
    ASSERT_GT(same_cell, n / 2) << "the samples must come in runs within a cell";
    HashGrid grid(rt, cfg, lay, stride, GetParam());
    std::vector<float> d_enc_host = test::random_vector(size_t(lay.enc_pad) * stride, 1.0f, 6);
    cl::Buffer<float> pos(rt, s.pos), d_enc(rt, d_enc_host), grads(rt, lay.total);
    grads.fill(rt, 3.0f);
    grid.backward(pos, d_enc, n, grads, true);
    ref::Rows d_rows(size_t(lay.enc_width) * n);
    for (uint32_t r = 0; r < lay.enc_width; ++r)
      for (uint32_t i = 0; i < n; ++i) d_rows[size_t(r) * n + i] = d_enc_host[size_t(r) * stride + i];
    auto want = ref::encode_backward(lay, cfg, s, d_rows);
    want.resize(lay.hash_count);
    // A coarse entry sums up to ~1000 terms of magnitude <= 1, in runs: float rounding well below
    // 1e-5 of the largest entry.
    test::expect_close(grads.read(rt, lay.hash_count), want, 1e-4, 1e-5 * test::max_abs(want),
                       "hash gradient of samples along rays, " + std::to_string(features) + " features");
  }
}

TEST(HashGrid, AtomicBackwardOfTheGpuVariantMatchesReference) {
  auto& rt = test::runtime();
  HashSetup h;
  HashGrid grid(rt, h.cfg, h.lay, h.stride, KernelVariant::Gpu);
  std::vector<float> d_enc_host = test::random_vector(size_t(h.lay.enc_pad) * h.stride, 1.0f, 5);
  cl::Buffer<float> pos(rt, h.s.pos), d_enc(rt, d_enc_host), grads(rt, h.lay.total);
  grid.backward(pos, d_enc, h.n, grads, false);
  ref::Rows d_rows(size_t(h.lay.enc_width) * h.n);
  for (uint32_t r = 0; r < h.lay.enc_width; ++r)
    for (uint32_t i = 0; i < h.n; ++i) d_rows[size_t(r) * h.n + i] = d_enc_host[size_t(r) * h.stride + i];
  auto want = ref::encode_backward(h.lay, h.cfg, h.s, d_rows);
  want.resize(h.lay.hash_count);
  // Same sums as the deterministic path in another order.
  test::expect_close(grads.read(rt, h.lay.hash_count), want, 1e-4, 1e-5 * test::max_abs(want),
                     "atomic hash gradient");
}
