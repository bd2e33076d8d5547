// The neural field of the NeRF: a multiresolution hash encoding (Instant-NGP) feeding a tiny
// density MLP (raw density + geometry features) and a colour MLP (spherical-harmonics direction +
// geometry features -> RGB), trained by Adam. All parameters live in one flat device buffer and
// their gradients in another; every kernel is deterministic (no float atomics) unless the caller
// asks for the non-deterministic GPU path. The two MLPs run as one fused chain (all layers per
// 32-sample slab on a CPU, kernels/mlp/mlp_chain.cl; per sample on a GPU, mlp_chain_per_sample.cl);
// activations and deltas are kept per sample for the backward pass, about 2 x 260 floats per sample of
// max_batch with the default shapes.
//
// Per-sample arrays are structure-of-arrays Buffer<float> with stride max_batch():
//   positions 3*max_batch (x[0..n) then y then z), in [0,1]^3 (the caller normalises the AABB);
//   directions 3*max_batch, unit vectors; rgb 3*max_batch in [0,1]; sigma max_batch, >= 0.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/runtime.h"
#include "host/field/field_config.h"
#include "host/field/kernel_variant.h"
#include "kernels/mlp/mlp_types.h"

namespace lorgnette::field {

class HashGrid;
class Mlp;
class Adam;
class FieldInfer;

// Adam's state over the flat parameter vector: first and second moments and the step count (the
// bias correction's t). A training checkpoint keeps it so a resumed training takes the same steps.
struct OptimiserState {
  std::vector<float> m, v;
  uint64_t t = 0;
};

class Field {
 public:
  // variant: the kernels shaped for the device (Auto) or forced (tests run the GPU ones on PoCL).
  Field(cl::Runtime& rt, const FieldConfig& cfg, uint32_t max_batch, uint64_t seed, bool deterministic,
        KernelVariant variant = KernelVariant::Auto);
  ~Field();
  Field(const Field&) = delete;
  Field& operator=(const Field&) = delete;

  uint32_t max_batch() const { return max_batch_; }  // sample capacity, a multiple of 64

  // Inference: sigma = exp(min(raw density, 15)). Invalidates a pending backward().
  void density(const cl::Buffer<float>& pos, uint32_t n, cl::Buffer<float>& sigma);
  // keep_for_backward = false on the CPU variant runs the fused inference kernel (field_infer.h):
  // the same sigma and rgb bit for bit, without the per-sample activation buffers.
  void forward(const cl::Buffer<float>& pos, const cl::Buffer<float>& dir, uint32_t n,
               cl::Buffer<float>& sigma, cl::Buffer<float>& rgb, bool keep_for_backward);
  // After forward(..., true) with the same n: gradients of the loss w.r.t. sigma and rgb (same
  // layouts) -> parameter gradients (overwritten, not accumulated).
  void backward(const cl::Buffer<float>& dL_dsigma, const cl::Buffer<float>& dL_drgb, uint32_t n);
  void adam_step(const AdamConfig& adam);  // one Adam step on all parameters

  const FieldConfig& config() const { return cfg_; }
  const ParamLayout& layout() const { return layout_; }
  uint64_t adam_steps() const { return adam_t_; }

  std::vector<float> download_params() const;
  // Size must be config().param_count(). Resets Adam (moments and step count): the optimiser
  // state of other parameters (e.g. from before a divergence) must not carry over.
  void upload_params(const std::vector<float>& params);
  std::vector<float> download_gradients() const;
  OptimiserState download_optimiser() const;
  // Parameters with the optimiser state they were trained with (a training checkpoint): the next
  // adam_step() is the one the interrupted training would have taken. Sizes must be param_count().
  void restore(const std::vector<float>& params, const OptimiserState& adam);
  // Device buffers (for tests and benchmarks).
  cl::Buffer<float>& params() { return params_; }
  cl::Buffer<float>& gradients() { return grads_; }

 private:
  void check_batch(const char* what, uint32_t n) const;
  void plan_rows();
  // The layered path's activation, delta and position buffers (about 2 x 1 KiB per sample of
  // max_batch): made on its first use, so a Field that only runs the fused inference never holds them.
  void ensure_layered_buffers();

  cl::Runtime& rt_;
  FieldConfig cfg_;
  ParamLayout layout_;
  uint32_t max_batch_ = 0;
  bool deterministic_ = true;
  cl::Buffer<float> params_, grads_, adam_m_, adam_v_;
  // All activations in one buffer and all deltas in another, [row][max_batch] with the same row
  // plan (encoding, density hidden, colour input = SH | geo, colour hidden..., RGB), so the fused
  // MLP chain addresses every layer by row. pos_copy_ keeps the positions for the hash backward.
  cl::Buffer<float> acts_, deltas_, pos_copy_, dw_partial_;
  MlpChainParams chain_{};  // the whole network; density() runs its first two layers
  uint32_t color_in_row_ = 0, geo_row_ = 0, rgb_row_ = 0, rows_ = 0;
  std::unique_ptr<HashGrid> hash_;
  std::unique_ptr<Mlp> mlp_;
  std::unique_ptr<Adam> adam_;
  std::unique_ptr<FieldInfer> infer_;  // CPU variant only (null on GPUs and for deep colour nets)
  uint32_t pending_backward_n_ = 0;    // n of the last forward(..., true); 0 = none
  bool hash_grads_zero_ = true;        // the hash part of grads_ is zero (construction, adam_step)
  uint64_t adam_t_ = 0;
};

}  // namespace lorgnette::field
