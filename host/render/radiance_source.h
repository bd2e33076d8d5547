// What the marcher asks of a volume: density and colour for a batch of samples, with the NeRF
// field's interface (host/field): structure-of-arrays buffers of stride max_batch(), positions
// normalised to the scene AABB, unit directions. The NeRF field and the analytic test fields
// (analytic_field.h) both implement it, so the marcher is tested on closed-form scenes. A source
// may also say how a kernel evaluates it per sample (in_kernel()), for the fused marcher
// (fused_marcher.h), which marches without handing batches to the field.
#pragma once
#include <cstdint>

#include "host/cl/buffer.h"

struct AnalyticFieldParams;  // kernels/march/march_types.h
namespace lorgnette::field {
class Field;
}

namespace lorgnette::render {

// What a kernel needs to evaluate the source itself: the analytic primitives or the NeRF field
// (its shape and parameter buffer); both null when the source can only be evaluated in batches.
struct InKernelField {
  const AnalyticFieldParams* analytic = nullptr;
  field::Field* nerf = nullptr;
};

class RadianceSource {
 public:
  virtual ~RadianceSource() = default;
  // Sample capacity of one evaluate() call and the SoA stride of its buffers.
  virtual uint32_t max_batch() const = 0;
  // pos, dir: 3 * max_batch(); sigma: max_batch(); rgb: 3 * max_batch(). Evaluates the first n.
  virtual void evaluate(const cl::Buffer<float>& pos, const cl::Buffer<float>& dir, uint32_t n,
                        cl::Buffer<float>& sigma, cl::Buffer<float>& rgb) = 0;
  virtual InKernelField in_kernel() { return {}; }
};

}  // namespace lorgnette::render
