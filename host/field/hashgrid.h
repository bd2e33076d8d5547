// Host side of the hash-encoding kernels (kernels/hashgrid/hashgrid.cl): owns the program and
// kernels and turns a ParamLayout into the kernels' parameter struct.
#pragma once
#include <cstdint>

#include "host/cl/buffer.h"
#include "host/cl/kernel.h"
#include "host/cl/runtime.h"
#include "host/field/field_config.h"
#include "host/field/kernel_variant.h"
#include "kernels/hashgrid/hashgrid_types.h"

namespace lorgnette::field {

HashgridParams make_hashgrid_params(const FieldConfig& cfg, const ParamLayout& layout, uint32_t stride);

class HashGrid {
 public:
  HashGrid(cl::Runtime& rt, const FieldConfig& cfg, const ParamLayout& layout, uint32_t stride,
           KernelVariant variant = KernelVariant::Auto);

  // enc[(l * F + f) * stride + i] for i < n; zeros for n <= i < round_up(n, 16).
  void encode(const cl::Buffer<float>& params, const cl::Buffer<float>& pos, uint32_t n,
              cl::Buffer<float>& enc);
  // Overwrites the hash part of grads with d loss / d table, given d loss / d enc.
  // deterministic=false on a GPU uses compare-and-swap float adds (faster, run-to-run order varies).
  // grads_zeroed: the caller guarantees the hash part is zero already (no clearing pass).
  void backward(const cl::Buffer<float>& pos, const cl::Buffer<float>& d_enc, uint32_t n,
                cl::Buffer<float>& grads, bool deterministic, bool grads_zeroed = false);

 private:
  cl::Runtime& rt_;
  HashgridParams base_;
  uint64_t hash_count_;
  bool gpu_;
  cl::Kernel encode_, backward_, backward_atomic_;
};

}  // namespace lorgnette::field
