// The GPU MLP chains forced on PoCL: the local-weights chain (mlp_chain_local.cl) against the
// per-sample chain that reads its weights from global memory (bit for bit: same summation order)
// and against the CPU chain (float16 lanes, another order: close), forward and backward, on the
// Field's default network with a sample count that leaves the last work-group partly empty.
// (Field.GpuKernelsMatchReference checks the whole GPU field against the double reference.)
#include "field_test_util.h"
#include "host/cl/buffer.h"
#include "host/field/mlp.h"

using namespace lorgnette;
using namespace lorgnette::field;

namespace {

struct ChainRun {
  std::vector<float> acts, deltas;
};

ChainRun run_chain(Mlp& mlp, const ChainPlan& plan, const std::vector<float>& params,
                   const std::vector<float>& acts0, const std::vector<float>& d_sigma,
                   const std::vector<float>& d_rgb, uint32_t n) {
  auto& rt = test::runtime();
  cl::Buffer<float> W(rt, params), acts(rt, acts0), deltas(rt, std::vector<float>(acts0.size(), 0.0f));
  cl::Buffer<float> ds(rt, d_sigma), drgb(rt, d_rgb);
  mlp.chain_forward(plan.chain, n, W, acts);
  mlp.chain_backward(plan.chain, n, W, acts, deltas, ds, drgb);
  return {acts.read(rt), deltas.read(rt)};
}

}  // namespace

TEST(MlpGpuChain, LocalWeightsMatchGlobalWeightsBitwiseAndTheCpuChain) {
  auto& rt = test::runtime();
  const FieldConfig cfg;  // the default network: 32 -> 64 -> 16, colour 32 -> 64 -> 64 -> 3
  const ParamLayout lay = make_layout(cfg);
  constexpr uint32_t kN = 700, kStride = 768;  // 700 = 2 full groups of 256 + 188
  const ChainPlan plan = plan_chain(lay, kStride);
  std::vector<float> params = test::random_vector(lay.total, 0.2f, 41);
  // Inputs: the encoding rows and the SH rows of the colour input; zeros for padded samples.
  std::vector<float> acts(size_t(plan.rows) * kStride, 0.0f),
      rnd = test::random_vector(acts.size(), 1.0f, 42);
  auto fill_rows = [&](uint32_t first, uint32_t count) {
    for (uint32_t r = first; r < first + count; ++r)
      for (uint32_t i = 0; i < kN; ++i) acts[size_t(r) * kStride + i] = rnd[size_t(r) * kStride + i];
  };
  fill_rows(0, lay.enc_pad);
  fill_rows(plan.color_in_row, lay.sh_count);
  const std::vector<float> d_sigma = test::random_vector(kN, 1.0f, 43);
  const std::vector<float> d_rgb = test::random_vector(3 * kStride, 1.0f, 44);
  uint32_t largest = 0;
  for (const auto& L : lay.density) largest = std::max(largest, uint32_t(L.count()));
  for (const auto& L : lay.color) largest = std::max(largest, uint32_t(L.count()));

  Mlp local(rt, kStride, KernelVariant::Gpu, largest), global(rt, kStride, KernelVariant::Gpu),
      cpu(rt, kStride, KernelVariant::Cpu);
  ASSERT_TRUE(local.local_weights()) << "the layers (" << largest * 4 << " bytes) fit PoCL's local memory";
  ASSERT_FALSE(global.local_weights());
  const ChainRun a = run_chain(local, plan, params, acts, d_sigma, d_rgb, kN);
  const ChainRun b = run_chain(global, plan, params, acts, d_sigma, d_rgb, kN);
  const ChainRun c = run_chain(cpu, plan, params, acts, d_sigma, d_rgb, kN);
  EXPECT_EQ(a.acts, b.acts) << "forward: local and global weights sum in the same order";
  EXPECT_EQ(a.deltas, b.deltas) << "backward: local and global weights sum in the same order";
  // The CPU chain sums the same products in the same order per sample but through fused float16
  // lanes; activations and deltas are O(1) sums of 32..64 terms: 1e-5 absolute + 1e-5 relative.
  auto rows = [&](const std::vector<float>& v) {
    ref::Rows r;
    for (uint32_t row = 0; row < plan.rows; ++row)
      for (uint32_t i = 0; i < kN; ++i) r.push_back(v[size_t(row) * kStride + i]);
    return r;
  };
  test::expect_close(rows(a.acts), rows(c.acts), 1e-5, 1e-5, "forward, GPU local vs CPU chain");
  test::expect_close(rows(a.deltas), rows(c.deltas), 1e-5, 1e-5, "backward, GPU local vs CPU chain");
}
