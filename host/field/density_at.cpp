// The field's density at host points; see density_at.h.
#include "host/field/density_at.h"

#include <algorithm>

#include "host/cl/buffer.h"

namespace lorgnette::field {

std::vector<float> density_at(Field& field, cl::Runtime& rt,
                              const std::vector<std::array<float, 3>>& unit_points) {
  std::vector<float> sigma(unit_points.size(), 0.0f);
  if (unit_points.empty()) return sigma;
  const uint32_t batch = field.max_batch();
  cl::Buffer<float> pos(rt, size_t(3) * batch), out(rt, batch);
  std::vector<float> soa(size_t(3) * batch, 0.0f);  // x of every point, then y, then z
  for (size_t s0 = 0; s0 < unit_points.size(); s0 += batch) {
    const uint32_t n = uint32_t(std::min<size_t>(batch, unit_points.size() - s0));
    for (uint32_t i = 0; i < n; ++i)
      for (int a = 0; a < 3; ++a) soa[size_t(a) * batch + i] = unit_points[s0 + i][size_t(a)];
    pos.write(rt, soa);
    field.density(pos, n, out);
    out.read(rt, sigma.data() + s0, n);
  }
  return sigma;
}

}  // namespace lorgnette::field
