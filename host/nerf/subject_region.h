// Keeping only the subject in a model trained on a mask-less capture: the connected region of the
// occupancy grid that holds the middle of the subject box (head, hair, neck; whatever touches them),
// so floaters and stray room density elsewhere in the box are dropped from every render, the fit
// and the snapshot. The box comes from the face (landmark head box), so its middle is the head.
#pragma once
#include <cstdint>
#include <string>

#include "host/nerf/snapshot.h"

namespace lorgnette::nerf {

struct SubjectRegionReport {
  bool found = false;              // a seed cell was occupied
  uint64_t kept = 0, removed = 0;  // occupied cells
  std::string summary() const;
};

// seed_radius: fraction of the grid's side around its centre whose occupied cells seed the flood
// fill (26-connected). Cells outside the region are cleared (bits and density). When no seed cell is
// occupied the grid is left unchanged and found is false.
SubjectRegionReport keep_central_region(OccupancyGrid& grid, float seed_radius = 0.2f);

}  // namespace lorgnette::nerf
