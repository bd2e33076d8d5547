// The MLP weight gradient's GPU path (mlp_weight_grad_partial_tiled, forced on PoCL) split into as
// many chunks as the device's compute units call for: the chunk rule itself, and the gradient for
// chunk counts of 1, a count that does not divide the batch, 128 (the old cap) and counts above it
// (folded into lanes before the last sum), each against
//  - a host float replay of the documented summation order (bit for bit: per chunk, the samples in
//    order by fma; then the chunks in order, or lane r's chunks r, r + 32, ... and then the lanes),
//  - the double reference dz x^T (a tolerance from the sum of |terms|), and
//  - a second run with the same split (bit for bit).
#include <cmath>

#include "field_test_util.h"
#include "host/cl/buffer.h"
#include "host/field/mlp.h"

using namespace lorgnette;
using namespace lorgnette::field;

namespace {

// 19990 samples: the padded tail (to 20000) carries zeros, as in the Field, and no chunk count
// below divides 19990.
constexpr uint32_t kIn = 32, kOut = 32, kN = 19990, kStride = 20032;

LayerShape layer() {
  LayerShape L;
  L.in = L.in_pad = kIn;
  L.out = L.out_pad = kOut;
  L.offset = 8;  // the gradient lands at an offset, as every layer but the first does
  return L;
}

struct Inputs {
  std::vector<float> x, dz;  // [kIn][kStride], [kOut][kStride], zero from sample kN on
};

Inputs make_inputs() {
  Inputs in{test::random_vector(size_t(kIn) * kStride, 1.0f, 71),
            test::random_vector(size_t(kOut) * kStride, 1.0f, 72)};
  for (auto* v : {&in.x, &in.dz})
    for (size_t r = 0; r < v->size() / kStride; ++r)
      for (uint32_t i = kN; i < kStride; ++i) (*v)[r * kStride + i] = 0.0f;
  return in;
}

// The device's order replayed on the host in float (see mlp.cl: the tiled partials, the fold, the
// reduce). Samples up to n16 are summed, the padded ones being zeros.
std::vector<float> replay(const Inputs& in, const GradChunks& g) {
  const uint32_t n16 = (kN + 15) / 16 * 16, count = kIn * kOut;
  std::vector<float> partial(size_t(g.chunks) * count);
  for (uint32_t c = 0; c < g.chunks; ++c)
    for (uint32_t e = 0; e < count; ++e) {
      const float* d = in.dz.data() + size_t(e / kIn) * kStride;
      const float* x = in.x.data() + size_t(e % kIn) * kStride;
      float a = 0.0f;
      for (uint32_t i = c * g.chunk; i < std::min(n16, (c + 1) * g.chunk); ++i) a = std::fma(d[i], x[i], a);
      partial[size_t(c) * count + e] = a;
    }
  uint32_t terms = g.chunks;
  if (g.chunks > kGradFlatReduceMax) {
    for (uint32_t r = 0; r < kGradFoldLanes; ++r)
      for (uint32_t e = 0; e < count; ++e) {
        float s = 0.0f;
        for (uint32_t c = r; c < g.chunks; c += kGradFoldLanes) s += partial[size_t(c) * count + e];
        partial[size_t(r) * count + e] = s;
      }
    terms = kGradFoldLanes;
  }
  std::vector<float> grads(count);
  for (uint32_t e = 0; e < count; ++e) {
    float s = 0.0f;
    for (uint32_t c = 0; c < terms; ++c) s += partial[size_t(c) * count + e];
    grads[e] = s;
  }
  return grads;
}

// The weight gradient on a runtime whose GPU split is capped at `groups` work-groups.
std::vector<float> device_grad(const Inputs& in, uint32_t groups, GradChunks& used) {
  cl::RuntimeOptions ro;
  ro.mlp_grad_groups = groups;
  cl::Runtime rt(ro);
  Mlp mlp(rt, kStride, KernelVariant::Gpu);
  const LayerShape L = layer();
  used = mlp.weight_grad_chunks(L, kN);
  cl::Buffer<float> x(rt, in.x), dz(rt, in.dz), grads(rt, std::vector<float>(L.offset + L.count(), -1.0f));
  cl::Buffer<float> partial(rt, size_t(mlp.max_grad_chunks()) * L.count());
  mlp.weight_grad(L, {&x, 0, &dz, 0}, kN, partial, grads);
  std::vector<float> all = grads.read(rt);
  for (size_t i = 0; i < L.offset; ++i) EXPECT_EQ(all[i], -1.0f) << "written before the layer's offset";
  return {all.begin() + L.offset, all.end()};
}

}  // namespace

TEST(MlpGradSplit, GpuGroupsFollowTheComputeUnits) {
  EXPECT_EQ(gpu_grad_groups(132), 132 * kGradGroupsPerComputeUnit);
  EXPECT_EQ(gpu_grad_groups(2), 2 * kGradGroupsPerComputeUnit);
  EXPECT_EQ(gpu_grad_groups(0), kGradGroupsPerComputeUnit) << "a device reporting no units still gets groups";
  EXPECT_EQ(gpu_grad_groups(132, 128), 128u) << "an explicit cap wins";
  // An H200 (132 SMs): a 2^18 batch fills every SM several times over, in chunks of whole tiles.
  GradChunks h200 = grad_chunks(1u << 18, kGradChunkGpuMin, gpu_grad_groups(132));
  EXPECT_EQ(h200.chunks, 1024u);
  EXPECT_EQ(h200.chunk, 256u);
  // The cap of 128 gives the old fixed split (chunk target 512, at most 128) at the GPU batches.
  for (uint32_t n : {1u << 16, 1u << 18}) {
    GradChunks old = grad_chunks(n, 512, 128), capped = grad_chunks(n, kGradChunkGpuMin, 128);
    EXPECT_EQ(old.chunks, capped.chunks) << n;
    EXPECT_EQ(old.chunk, capped.chunk) << n;
  }
  // No chunk below the minimum, whatever the cap; every sample covered.
  for (uint32_t n : {1u, 100u, 5000u, 19990u, 65536u}) {
    GradChunks g = grad_chunks(n, kGradChunkGpuMin, 100000);
    EXPECT_GE(g.chunk, std::min<uint32_t>(kGradChunkGpuMin, (n + 15) / 16 * 16)) << n;
    EXPECT_GE(g.chunk * g.chunks, n) << n;
    EXPECT_LT((g.chunks - 1) * g.chunk, (n + 15) / 16 * 16) << n << ": an empty chunk";
  }
}

TEST(MlpGradSplit, EveryChunkCountMatchesItsOrderAndTheReference) {
  const Inputs in = make_inputs();
  // The double reference and the sum of |terms| per weight (the scale of float rounding).
  std::vector<double> ref(kIn * kOut), mag(kIn * kOut);
  for (uint32_t e = 0; e < kIn * kOut; ++e)
    for (uint32_t i = 0; i < kN; ++i) {
      const double t = double(in.dz[size_t(e / kIn) * kStride + i]) * in.x[size_t(e % kIn) * kStride + i];
      ref[e] += t;
      mag[e] += std::fabs(t);
    }
  // Caps and the chunk counts they give for 19990 samples (chunks of at least 128):
  //   1 -> 1; 7 -> 7 (the last chunk shorter); 128 -> 125; 150 -> 139 and 1000 -> 157 (folded).
  const std::vector<std::pair<uint32_t, uint32_t>> cases = {
      {1, 1}, {7, 7}, {128, 125}, {150, 139}, {1000, 157}};
  for (const auto& [groups, expect_chunks] : cases) {
    SCOPED_TRACE("cap " + std::to_string(groups));
    GradChunks used;
    const std::vector<float> got = device_grad(in, groups, used);
    ASSERT_EQ(used.chunks, expect_chunks);
    if (groups == 7) {
      EXPECT_NE(20000u % used.chunk, 0u) << "the chunk should not divide the batch";
    }
    EXPECT_EQ(got, replay(in, used)) << "the device sums in the documented order";
    // Float sums of 19990 products of O(1) values in chunks: rounding is far below 1e-6 of the sum
    // of |terms| (one chunk of 128 samples lost or doubled is about 1e-2 of it).
    for (uint32_t e = 0; e < kIn * kOut; ++e)
      ASSERT_NEAR(got[e], ref[e], 1e-6 * mag[e]) << "weight " << e << ", " << used.chunks << " chunks";
    GradChunks again;
    EXPECT_EQ(device_grad(in, groups, again), got) << "the same split gives the same bits";
  }
}
