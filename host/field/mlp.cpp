// Tiny-MLP launches; see mlp.h.
#include "host/field/mlp.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace lorgnette::field {
namespace {
constexpr size_t kLocal = 8;            // 32-sample work-items per work-group (2, 8 and 16 measured alike)
constexpr size_t kLocalPerSample = 64;  // GPU chains: one sample per work-item, two warps per group
// Local-weights GPU chains: 256 samples share one copy of each layer's weights (up to 64 x 64 = 16
// loads per work-item per layer against 4096 multiply-adds).
constexpr size_t kLocalWeights = 256;
uint32_t round16(uint32_t n) { return (n + 15u) & ~15u; }
}  // namespace

GradChunks grad_chunks(uint32_t n, uint32_t chunk_target, uint32_t max_chunks) {
  const uint32_t n16 = round16(n);
  GradChunks g;
  g.chunks = std::clamp<uint32_t>((n16 + chunk_target - 1) / chunk_target, 1, std::max(1u, max_chunks));
  g.chunk = std::max<uint32_t>(16, round16((n16 + g.chunks - 1) / g.chunks));
  g.chunks = std::max<uint32_t>(1, (n16 + g.chunk - 1) / g.chunk);
  return g;
}

uint32_t gpu_grad_groups(uint32_t compute_units, uint32_t requested) {
  return requested ? requested : kGradGroupsPerComputeUnit * std::max(1u, compute_units);
}

// Rows of acts_/deltas_: encoding (row 0: the hash kernels use it directly), density hidden,
// colour input (SH then geo features, raw density first), colour hidden layers, RGB (4 rows).
ChainPlan plan_chain(const ParamLayout& lay, uint32_t stride) {
  ChainPlan plan;
  const uint32_t sh_pad = pad4(lay.sh_count);
  uint32_t row = lay.enc_pad;
  const uint32_t dens_hidden_row = row;
  row += lay.density[0].out_pad;
  plan.color_in_row = row;
  plan.geo_row = row + sh_pad;
  row += lay.color_in_pad;
  MlpChainParams& c = plan.chain;
  c = MlpChainParams{};
  c.stride = stride;
  auto add = [&c](const LayerShape& L, uint32_t act, uint32_t x_row, uint32_t y_row, uint32_t mask,
                  uint32_t k_begin) {
    const uint32_t l = c.layers++;
    c.in[l] = L.in_pad;
    c.out[l] = L.out_pad;
    c.w_offset[l] = uint32_t(L.offset);
    c.act[l] = act;
    c.x_row[l] = c.dx_row[l] = x_row;  // deltas use the activations' row plan
    c.y_row[l] = c.dy_row[l] = y_row;
    c.mask[l] = mask;
    c.k_begin[l] = k_begin;
  };
  add(lay.density[0], LGN_ACT_RELU, 0, dens_hidden_row, 0, 0);
  add(lay.density[1], LGN_ACT_NONE, dens_hidden_row, plan.geo_row, 1, 0);
  const size_t last = lay.color.size() - 1;
  uint32_t x_row = plan.color_in_row;
  for (size_t h = 0; h <= last; ++h) {
    const uint32_t y_row = row;
    row += lay.color[h].out_pad;
    // Colour layer 0's input delta is only needed for the geo rows (not the SH ones).
    add(lay.color[h], h == last ? LGN_ACT_SIGMOID : LGN_ACT_RELU, x_row, y_row, h > 0, h == 0 ? sh_pad : 0);
    x_row = y_row;
  }
  if (c.layers > LGN_MLP_MAX_LAYERS) throw std::invalid_argument("too many colour layers for the fused MLP");
  plan.rgb_row = x_row;
  c.rgb_row = plan.rgb_row;
  c.raw_row = plan.geo_row;
  c.geo_layer = 2;
  plan.rows = row;
  return plan;
}

Mlp::Mlp(cl::Runtime& rt, uint32_t stride, KernelVariant variant, uint32_t largest_layer)
    : rt_(rt), stride_(stride), gpu_(use_gpu_variant(rt, variant)) {
  cl_program prog = rt.program("mlp/mlp.cl");
  forward_ = cl::Kernel(prog, "mlp_forward");
  backward_input_ = cl::Kernel(prog, "mlp_backward_input");
  grad_partial_ = cl::Kernel(prog, "mlp_weight_grad_partial");
  grad_reduce_ = cl::Kernel(prog, "mlp_weight_grad_reduce");
  sh_ = cl::Kernel(prog, "mlp_sh_encode");
  sigma_ = cl::Kernel(prog, "mlp_sigma");
  if (gpu_) {
    grad_tiled_ = cl::Kernel(prog, "mlp_weight_grad_partial_tiled");
    grad_fold_ = cl::Kernel(prog, "mlp_weight_grad_fold");
    gpu_groups_ = gpu_grad_groups(rt.device().compute_units, rt.mlp_grad_groups());
  }
  if (gpu_ && largest_layer > 0 && uint64_t(largest_layer) * sizeof(float) <= rt.device().local_mem_bytes) {
    cl_program chain = rt.program("mlp/mlp_chain_local.cl");
    chain_fwd_ = cl::Kernel(chain, "mlp_chain_forward_local");
    chain_bwd_ = cl::Kernel(chain, "mlp_chain_backward_local");
    if (chain_fwd_.max_work_group_size(rt) >= kLocalWeights &&
        chain_bwd_.max_work_group_size(rt) >= kLocalWeights)
      local_floats_ = largest_layer;
  }
  if (!local_floats_) {
    cl_program chain = rt.program(gpu_ ? "mlp/mlp_chain_per_sample.cl" : "mlp/mlp_chain.cl");
    chain_fwd_ = cl::Kernel(chain, "mlp_chain_forward");
    chain_bwd_ = cl::Kernel(chain, "mlp_chain_backward");
  }
}

MlpParams Mlp::base(uint32_t n) const {
  MlpParams p{};
  p.n = n;
  p.n16 = round16(n);
  p.stride = stride_;
  return p;
}

void Mlp::forward(const LayerShape& L, const cl::Buffer<float>& params, const LayerIo& io, uint32_t n,
                  uint32_t act, uint32_t out_rows) {
  MlpParams p = base(n);
  p.in = L.in_pad;
  p.out = out_rows ? std::min(pad4(out_rows), L.out_pad) : L.out_pad;
  p.w_offset = uint32_t(L.offset);
  p.x_row = io.x_row;
  p.y_row = io.y_row;
  p.act = act;
  forward_.args(p, params, *io.x, *io.y).launch(rt_, (p.n16 + 31) / 32, kLocal);
}

void Mlp::backward_input(const LayerShape& L, const cl::Buffer<float>& params, const LayerIo& io, uint32_t n,
                         cl::Buffer<float>& dx, uint32_t dx_row, uint32_t k_begin, bool relu_mask) {
  MlpParams p = base(n);
  p.in = L.in_pad;
  p.out = L.out_pad;
  p.w_offset = uint32_t(L.offset);
  p.x_row = io.x_row;
  p.y_row = io.y_row;
  p.dx_row = dx_row;
  p.k_begin = k_begin;
  p.act = relu_mask ? LGN_ACT_RELU : LGN_ACT_NONE;
  backward_input_.args(p, params, *io.y, *io.x, dx).launch(rt_, (p.n16 + 31) / 32, kLocal);
}

namespace {
// The GPU kernel's group for a layer of `count` weights: count / LGN_MLP_GRAD_PER_ITEM work-items,
// whole warps of 64.
size_t tiled_group(size_t count) {
  return cl::round_up(std::max<size_t>(64, (count + LGN_MLP_GRAD_PER_ITEM - 1) / LGN_MLP_GRAD_PER_ITEM), 64);
}
// Its local scratch: the tile's input and delta rows, each padded by one float.
size_t tile_bytes(const LayerShape& L) {
  return size_t(L.in_pad + L.out_pad) * (LGN_MLP_GRAD_TILE + 1) * sizeof(float);
}
}  // namespace

bool Mlp::grad_tiled(const LayerShape& L) const {
  return gpu_ && tiled_group(size_t(L.out_pad) * L.in_pad) <= grad_tiled_.max_work_group_size(rt_) &&
         tile_bytes(L) <= rt_.device().local_mem_bytes;
}

GradChunks Mlp::weight_grad_chunks(const LayerShape& L, uint32_t n) const {
  return grad_tiled(L) ? grad_chunks(n, kGradChunkGpuMin, gpu_groups_)
                       : grad_chunks(n, kGradChunk, kMaxGradChunks);
}

void Mlp::weight_grad(const LayerShape& L, const LayerIo& io, uint32_t n, cl::Buffer<float>& partial,
                      cl::Buffer<float>& grads) {
  MlpParams p = base(n);
  p.in = L.in_pad;
  p.out = L.out_pad;
  p.w_offset = uint32_t(L.offset);
  p.x_row = io.x_row;
  p.y_row = io.y_row;
  const size_t count = size_t(p.out) * p.in;
  const bool tiled = grad_tiled(L);
  const GradChunks g = weight_grad_chunks(L, n);
  p.chunk = g.chunk;
  p.chunks = g.chunks;
  if (partial.size() < size_t(p.chunks) * count)
    throw std::invalid_argument(
        "Mlp::weight_grad: the partial buffer holds " + std::to_string(partial.size()) + " floats, needs " +
        std::to_string(size_t(p.chunks) * count) + " (max_grad_chunks() x the layer)");
  if (tiled) {
    const size_t group = tiled_group(count);
    grad_tiled_.args(p, *io.y, *io.x, partial, cl::LocalBytes{tile_bytes(L)})
        .launch(rt_, p.chunks * group, group);
  } else {
    const size_t blocks = size_t(p.out / 4) * (p.in / 4);
    grad_partial_.args(p, *io.y, *io.x, partial).launch2d(rt_, {blocks, p.chunks}, {16, 1});
  }
  if (p.chunks > kGradFlatReduceMax) {
    // Lane r of each weight sums chunks r, r + lanes, ... into partial[r]; then the lanes in order.
    p.aux = kGradFoldLanes;
    grad_fold_.args(p, partial).launch2d(rt_, {cl::round_up(count, 64), kGradFoldLanes}, {64, 1});
    p.chunks = kGradFoldLanes;
  }
  grad_reduce_.args(p, partial, grads).launch(rt_, size_t(p.out) * p.in, 64);
}

void Mlp::chain_forward(MlpChainParams p, uint32_t n, const cl::Buffer<float>& params,
                        cl::Buffer<float>& acts) {
  p.n = n;
  p.n16 = round16(n);
  if (local_floats_)
    chain_fwd_.args(p, params, acts, cl::LocalBytes{local_floats_ * sizeof(float)})
        .launch(rt_, p.n16, kLocalWeights);
  else if (gpu_)
    chain_fwd_.args(p, params, acts).launch(rt_, p.n16, kLocalPerSample);
  else
    chain_fwd_.args(p, params, acts).launch(rt_, (p.n16 + 31) / 32, kLocal);
}

void Mlp::chain_backward(MlpChainParams p, uint32_t n, const cl::Buffer<float>& params,
                         const cl::Buffer<float>& acts, cl::Buffer<float>& deltas,
                         const cl::Buffer<float>& d_sigma, const cl::Buffer<float>& d_rgb) {
  p.n = n;
  p.n16 = round16(n);
  if (local_floats_)
    chain_bwd_.args(p, params, acts, deltas, d_sigma, d_rgb, cl::LocalBytes{local_floats_ * sizeof(float)})
        .launch(rt_, p.n16, kLocalWeights);
  else if (gpu_)
    chain_bwd_.args(p, params, acts, deltas, d_sigma, d_rgb).launch(rt_, p.n16, kLocalPerSample);
  else
    chain_bwd_.args(p, params, acts, deltas, d_sigma, d_rgb).launch(rt_, (p.n16 + 31) / 32, kLocal);
}

void Mlp::sh_encode(const cl::Buffer<float>& dir, uint32_t n, uint32_t sh_count, cl::Buffer<float>& out,
                    uint32_t row) {
  MlpParams p = base(n);
  p.aux = sh_count;
  p.y_row = row;
  sh_.args(p, dir, out).launch(rt_, p.n16, 64);
}

void Mlp::sigma(const cl::Buffer<float>& geo, uint32_t raw_row, uint32_t n, cl::Buffer<float>& sigma) {
  MlpParams p = base(n);
  p.y_row = raw_row;
  sigma_.args(p, geo, sigma).launch(rt_, std::max<uint32_t>(n, 1), 64);
}

}  // namespace lorgnette::field
