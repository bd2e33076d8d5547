// What the marcher asks of a volume: density and colour for a batch of samples, with the NeRF
// field's interface (host/field): structure-of-arrays buffers of stride max_batch(), positions
// normalised to the scene AABB, unit directions. The NeRF field and the analytic test fields
// (analytic_field.h) both implement it, so the marcher is tested on closed-form scenes.
#pragma once
#include <cstdint>

#include "host/cl/buffer.h"

namespace lorgnette::render {

class RadianceSource {
 public:
  virtual ~RadianceSource() = default;
  // Sample capacity of one evaluate() call and the SoA stride of its buffers.
  virtual uint32_t max_batch() const = 0;
  // pos, dir: 3 * max_batch(); sigma: max_batch(); rgb: 3 * max_batch(). Evaluates the first n.
  virtual void evaluate(const cl::Buffer<float>& pos, const cl::Buffer<float>& dir, uint32_t n,
                        cl::Buffer<float>& sigma, cl::Buffer<float>& rgb) = 0;
};

}  // namespace lorgnette::render
