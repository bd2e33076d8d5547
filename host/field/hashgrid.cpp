// Hash-encoding launches; see hashgrid.h.
#include "host/field/hashgrid.h"

#include <cstring>
#include <string>

namespace lorgnette::field {

HashgridParams make_hashgrid_params(const FieldConfig& cfg, const ParamLayout& layout, uint32_t stride) {
  HashgridParams p;
  std::memset(&p, 0, sizeof(p));
  p.stride = stride;
  p.levels = cfg.levels;
  p.features = cfg.features_per_level;
  for (uint32_t l = 0; l < cfg.levels; ++l) {
    p.resolution[l] = layout.levels[l].resolution;
    p.size[l] = layout.levels[l].size;
    p.dense[l] = layout.levels[l].dense;
    p.offset[l] = uint32_t(layout.levels[l].offset);
  }
  return p;
}

HashGrid::HashGrid(cl::Runtime& rt, const FieldConfig& cfg, const ParamLayout& layout, uint32_t stride,
                   KernelVariant variant)
    : rt_(rt), base_(make_hashgrid_params(cfg, layout, stride)), hash_count_(layout.hash_count) {
  gpu_ = use_gpu_variant(rt, variant);
  const std::string options = variant == KernelVariant::Auto ? ""
                              : gpu_                         ? "-DLGN_HASHGRID_GPU=1"
                                                             : "-DLGN_HASHGRID_GPU=0";
  cl_program prog = rt.program("hashgrid/hashgrid.cl", options);
  encode_ = cl::Kernel(prog, "hashgrid_encode");
  backward_ = cl::Kernel(prog, "hashgrid_backward");
  if (gpu_) backward_atomic_ = cl::Kernel(prog, "hashgrid_backward_atomic");
}

void HashGrid::encode(const cl::Buffer<float>& params, const cl::Buffer<float>& pos, uint32_t n,
                      cl::Buffer<float>& enc) {
  HashgridParams p = base_;
  p.n = n;
  const size_t n16 = cl::round_up(n, 16);
  if (n16 == 0) return;
  if (gpu_)
    encode_.args(p, params, pos, enc).launch2d(rt_, {n16, p.levels}, {64, 1});
  else  // 16 samples per work-item (float16 vectors)
    encode_.args(p, params, pos, enc).launch2d(rt_, {n16 / 16, p.levels}, {8, 1});
}

void HashGrid::backward(const cl::Buffer<float>& pos, const cl::Buffer<float>& d_enc, uint32_t n,
                        cl::Buffer<float>& grads, bool deterministic, bool grads_zeroed) {
  HashgridParams p = base_;
  p.n = n;
  if (!grads_zeroed) grads.fill(rt_, 0.0f, 0, hash_count_);
  if (n == 0) return;
  if (!deterministic && backward_atomic_.get()) {
    backward_atomic_.args(p, pos, d_enc, grads).launch2d(rt_, {cl::round_up(n, 64), p.levels}, {64, 1});
    return;
  }
  if (gpu_)
    backward_.args(p, pos, d_enc, grads).launch(rt_, size_t(p.levels) * p.features, 1);
  else
    backward_.args(p, pos, d_enc, grads).launch(rt_, p.levels, 1);
}

}  // namespace lorgnette::field
