// Occupancy masks from a point test: a cell of the res^3 grid over `box` is allowed when any of its
// 8 corners or its centre passes `inside` (so thin parts of a shape still open the cells they cross).
// Used by the visual-hull mask of the sizing and the subject volume's mask. T is the arithmetic the
// points are computed in (double or float); `inside` takes a point as const T[3].
#pragma once
#include <cstdint>
#include <vector>

#include "host/nerf/snapshot.h"
#include "kernels/train/occupancy.h"

namespace lorgnette::nerf {

template <typename T, typename Inside>
std::vector<uint32_t> occupancy_mask_where(const Aabb& box, uint32_t res, Inside inside) {
  std::vector<uint32_t> bits(occ_word_count(res), 0u);
  for (uint32_t z = 0; z < res; ++z)
    for (uint32_t y = 0; y < res; ++y)
      for (uint32_t x = 0; x < res; ++x) {
        const uint32_t q[3] = {x, y, z};
        bool any = false;
        for (int k = 0; k < 9 && !any; ++k) {  // the 8 corners, then the centre
          T p[3];
          for (int a = 0; a < 3; ++a) {
            const T f = k == 8 ? T(0.5) : T((k >> a) & 1);
            p[a] = T(box.min[a]) + (T(q[a]) + f) / T(res) * T(box.extent(a));
          }
          any = inside(p);
        }
        const uint32_t cell = x + res * (y + res * z);
        if (any) bits[cell >> 5] |= 1u << (cell & 31u);
      }
  return bits;
}

}  // namespace lorgnette::nerf
