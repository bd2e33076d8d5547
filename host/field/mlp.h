// Host side of the tiny-MLP kernels: single dense layers and fused chains of them
// (kernels/mlp/mlp.cl, mlp_chain.cl or mlp_chain_per_sample.cl), deterministic weight gradients (per-chunk
// partials + fixed-order reduction), and the small head kernels (SH encoding, sigma) the Field uses.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "host/cl/buffer.h"
#include "host/cl/kernel.h"
#include "host/cl/runtime.h"
#include "host/field/field_config.h"
#include "host/field/kernel_variant.h"
#include "kernels/mlp/mlp_types.h"

namespace lorgnette::field {

// Where a layer reads and writes: buffers plus first rows (all [row][stride]).
struct LayerIo {
  const cl::Buffer<float>* x = nullptr;  // layer input (activated output of the previous layer)
  uint32_t x_row = 0;
  cl::Buffer<float>* y = nullptr;  // forward: output; backward: the output delta dz
  uint32_t y_row = 0;
};

// Weight-gradient chunking for n samples: fixed for a given n (and, on a GPU, the device's work-group
// cap), so the sums are reproducible.
struct GradChunks {
  uint32_t chunk = 16, chunks = 1;
};
// chunk_target: samples per chunk aimed at; max_chunks: the most chunks (work-groups) allowed.
GradChunks grad_chunks(uint32_t n, uint32_t chunk_target, uint32_t max_chunks);
// CPU path (mlp_weight_grad_partial): a chunk's input and delta rows (up to 128 rows x 2048 floats
// = 1 MiB) stay in the L2 cache while the work-groups of its 4x4 weight blocks run one after
// another (measured: 512 and 4096 were slower on the 2-core Xeon). Its parallelism comes from the
// weight blocks, so the chunk count is not tied to the device.
constexpr uint32_t kGradChunk = 2048;
constexpr uint32_t kMaxGradChunks = 128;
// GPU path (mlp_weight_grad_partial_tiled): one work-group per chunk, each holding a whole layer's
// weights, so the chunks are what fills the device. They follow its compute units: at most
// kGradGroupsPerComputeUnit per unit (8 groups of 256 work-items are the 2048 resident threads of
// an NVIDIA SM), and no chunk under kGradChunkGpuMin samples, so a group's partial (in * out floats)
// stays under a quarter of the rows it reads ((in + out) * chunk floats).
constexpr uint32_t kGradGroupsPerComputeUnit = 8;
constexpr uint32_t kGradChunkGpuMin = 128;
// The work-group cap of the GPU path: `requested` when not 0 (benchmarks time the old fixed 128),
// else kGradGroupsPerComputeUnit per compute unit.
uint32_t gpu_grad_groups(uint32_t compute_units, uint32_t requested = 0);
// Partials above this many chunks are first folded into kGradFoldLanes lanes (lane r sums chunks
// r, r + lanes, ... in order), then the lanes are summed in order: a fixed order for a given chunk
// count, so still deterministic, and a reduction with lanes x in x out work-items instead of one
// loop of up to a thousand loads per weight. Up to this many, one loop per weight sums the chunks
// in order, as the CPU path always has.
constexpr uint32_t kGradFlatReduceMax = 128;
constexpr uint32_t kGradFoldLanes = 32;

// The Field's network as one fused chain: density layers, then colour layers, with every
// activation (and delta) at a row of one [rows][stride] buffer.
struct ChainPlan {
  MlpChainParams chain{};
  uint32_t color_in_row = 0, geo_row = 0, rgb_row = 0, rows = 0;
};
ChainPlan plan_chain(const ParamLayout& layout, uint32_t stride);

class Mlp {
 public:
  // The fused chains come in a CPU variant (mlp_chain.cl) and a GPU one: the weights of each layer
  // in local memory (mlp_chain_local.cl) when the largest layer (largest_layer floats, in * out
  // padded) fits the device's local memory, else read from global memory (mlp_chain_per_sample.cl).
  Mlp(cl::Runtime& rt, uint32_t stride, KernelVariant variant = KernelVariant::Auto,
      uint32_t largest_layer = 0);
  bool local_weights() const { return local_floats_ > 0; }

  // y = act(W x) for output rows [0, out_rows) (out_rows = 0: all of the layer's rows).
  void forward(const LayerShape& L, const cl::Buffer<float>& params, const LayerIo& io, uint32_t n,
               uint32_t act, uint32_t out_rows = 0);
  // dx[dx_row + k] = (W^T dz)[k] for k >= k_begin, times (x[k] > 0) when relu_mask.
  void backward_input(const LayerShape& L, const cl::Buffer<float>& params, const LayerIo& io, uint32_t n,
                      cl::Buffer<float>& dx, uint32_t dx_row, uint32_t k_begin, bool relu_mask);
  // The most weight-gradient chunks this Mlp splits a layer into (its partial buffer holds that
  // many times the largest layer's weights).
  uint32_t max_grad_chunks() const { return gpu_ ? std::max(kMaxGradChunks, gpu_groups_) : kMaxGradChunks; }
  // The chunking weight_grad uses for layer L over n samples.
  GradChunks weight_grad_chunks(const LayerShape& L, uint32_t n) const;
  // grads[W] = sum over samples of dz x^T (overwrites). partial: max_grad_chunks() * L.count() floats.
  void weight_grad(const LayerShape& L, const LayerIo& io, uint32_t n, cl::Buffer<float>& partial,
                   cl::Buffer<float>& grads);

  // Fused chains (see MlpChainParams); p.n and p.n16 are set from n.
  void chain_forward(MlpChainParams p, uint32_t n, const cl::Buffer<float>& params, cl::Buffer<float>& acts);
  void chain_backward(MlpChainParams p, uint32_t n, const cl::Buffer<float>& params,
                      const cl::Buffer<float>& acts, cl::Buffer<float>& deltas,
                      const cl::Buffer<float>& d_sigma, const cl::Buffer<float>& d_rgb);

  // rows [row, row + sh_count) of `out` = SH basis of the directions.
  void sh_encode(const cl::Buffer<float>& dir, uint32_t n, uint32_t sh_count, cl::Buffer<float>& out,
                 uint32_t row);
  void sigma(const cl::Buffer<float>& geo, uint32_t raw_row, uint32_t n, cl::Buffer<float>& sigma);

 private:
  MlpParams base(uint32_t n) const;

  cl::Runtime& rt_;
  uint32_t stride_;
  bool gpu_;
  uint32_t local_floats_ = 0;  // local scratch of the local-weights chain (0: not used)
  uint32_t gpu_groups_ = 0;    // the GPU path's work-group cap (gpu_grad_groups)
  cl::Kernel forward_, backward_input_, grad_partial_, grad_reduce_, sh_, sigma_, chain_fwd_, chain_bwd_;
  cl::Kernel grad_tiled_, grad_fold_;          // GPU weight-gradient partials and their fold into lanes
  bool grad_tiled(const LayerShape& L) const;  // whether layer L takes the GPU path
};

}  // namespace lorgnette::field
