// Host side of the field's fused inference on CPUs (kernels/field/field_infer.cl): the whole
// forward of a Field for a batch of samples in one launch, each work-item's activations in local
// scratch. Field::forward(..., keep_for_backward = false) runs it on the CPU variant; it gives the
// layered forward's sigma and rgb bit for bit, so training keeps the layered path (it needs the
// activations afterwards) and nothing else changes.
#pragma once
#include <cstdint>

#include "host/cl/buffer.h"
#include "host/cl/kernel.h"
#include "host/cl/runtime.h"
#include "host/field/field_config.h"
#include "kernels/field/field_infer_types.h"

namespace lorgnette::field {

// The kernel's parameters for a Field of this shape whose per-sample arrays have stride `stride`
// (n and n16 are set per launch). Throws std::invalid_argument when the network is too deep.
FieldInferParams make_infer_params(const FieldConfig& cfg, const ParamLayout& layout, uint32_t stride);

class FieldInfer {
 public:
  // Whether the fused kernel handles this shape (density 2 + colour layers <= LGN_INFER_MAX_LAYERS)
  // and its work-group's scratch fits the device's local memory of local_mem_bytes.
  static bool supports(const ParamLayout& layout, uint64_t local_mem_bytes = UINT64_MAX);
  // Local scratch of one work-group for this shape, in bytes.
  static uint64_t local_bytes(const ParamLayout& layout);
  FieldInfer(cl::Runtime& rt, const FieldConfig& cfg, const ParamLayout& layout, uint32_t stride);

  // sigma[i], rgb[c * stride + i] for i < n, from positions and unit directions of stride `stride`.
  void run(const cl::Buffer<float>& params, const cl::Buffer<float>& pos, const cl::Buffer<float>& dir,
           uint32_t n, cl::Buffer<float>& sigma, cl::Buffer<float>& rgb);

 private:
  cl::Runtime& rt_;
  FieldInferParams base_;
  cl::Kernel kernel_;
};

}  // namespace lorgnette::field
