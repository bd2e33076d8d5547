// The subject's connected region on the occupancy grid; see subject_region.h.
#include "host/nerf/subject_region.h"

#include <fmt/format.h>

#include <cmath>
#include <vector>

namespace lorgnette::nerf {
namespace {

bool bit(const std::vector<uint32_t>& bits, uint64_t cell) { return (bits[cell >> 5] >> (cell & 31u)) & 1u; }

}  // namespace

std::string SubjectRegionReport::summary() const {
  if (!found)
    return "subject region: nothing occupied near the middle of the subject box; the model was left as it is";
  return fmt::format(
      "subject region: kept {} occupied cells connected to the middle of the subject box, removed {} "
      "({:.1f} %) elsewhere",
      kept, removed, kept + removed ? 100.0 * double(removed) / double(kept + removed) : 0.0);
}

SubjectRegionReport keep_central_region(OccupancyGrid& grid, float seed_radius) {
  const int res = int(grid.res);
  const uint64_t cells = uint64_t(res) * res * res;
  std::vector<uint8_t> keep(cells, 0);
  std::vector<uint64_t> stack;
  const float c = 0.5f * float(res), r = seed_radius * float(res);
  for (int z = 0; z < res; ++z)
    for (int y = 0; y < res; ++y)
      for (int x = 0; x < res; ++x) {
        float dx = x + 0.5f - c, dy = y + 0.5f - c, dz = z + 0.5f - c;
        uint64_t cell = uint64_t(x) + uint64_t(res) * (uint64_t(y) + uint64_t(res) * uint64_t(z));
        if (dx * dx + dy * dy + dz * dz <= r * r && bit(grid.bits, cell))
          keep[cell] = 1, stack.push_back(cell);
      }
  SubjectRegionReport rep;
  rep.found = !stack.empty();
  if (!rep.found) return rep;
  while (!stack.empty()) {
    uint64_t cell = stack.back();
    stack.pop_back();
    int x = int(cell % res), y = int((cell / res) % res), z = int(cell / (uint64_t(res) * res));
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          int nx = x + dx, ny = y + dy, nz = z + dz;
          if (nx < 0 || ny < 0 || nz < 0 || nx >= res || ny >= res || nz >= res) continue;
          uint64_t n = uint64_t(nx) + uint64_t(res) * (uint64_t(ny) + uint64_t(res) * uint64_t(nz));
          if (!keep[n] && bit(grid.bits, n)) keep[n] = 1, stack.push_back(n);
        }
  }
  for (uint64_t cell = 0; cell < cells; ++cell) {
    if (!bit(grid.bits, cell)) continue;
    if (keep[cell]) {
      ++rep.kept;
    } else {
      ++rep.removed;
      grid.bits[cell >> 5] &= ~(1u << (cell & 31u));
      if (!grid.density.empty()) grid.density[cell] = 0.0f;
    }
  }
  return rep;
}

}  // namespace lorgnette::nerf
