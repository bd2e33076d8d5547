// Host side of the Adam kernel (kernels/adam/adam.cl): bias-corrected Adam over the flat
// parameter vector with weight decay on the MLP part.
#pragma once
#include <cstdint>

#include "host/cl/buffer.h"
#include "host/cl/kernel.h"
#include "host/cl/runtime.h"
#include "host/field/field_config.h"
#include "kernels/adam/adam_types.h"

namespace lorgnette::field {

// The kernel parameters of step t (1-based) of Adam with `cfg` over `count` parameters.
AdamParams make_adam_params(const AdamConfig& cfg, uint64_t t, uint32_t count, uint32_t mlp_offset);

class Adam {
 public:
  explicit Adam(cl::Runtime& rt);
  // Clears grads [0, p.clear_below) after use.
  void step(const AdamParams& p, cl::Buffer<float>& params, cl::Buffer<float>& grads, cl::Buffer<float>& m,
            cl::Buffer<float>& v);

 private:
  cl::Runtime& rt_;
  cl::Kernel step_;
};

}  // namespace lorgnette::field
