// Occupancy-grid update points: one jittered position per listed cell (new jitter every update), in
// normalised coordinates, for Field::density. The host folds the densities
// into the grid (EMA, threshold, bitfield) in a fixed order.
#include "train/occupancy.h"
#include "train/train_types.h"

__kernel void occupancy_points(const OccParams p, __global const uint* cells, __global float* pos) {
  uint i = get_global_id(0);
  if (i >= p.n) return;
  uint cell = cells[p.first_cell + i];
  uint x = cell % p.res, y = (cell / p.res) % p.res, z = cell / (p.res * p.res);
  float inv = 1.0f / (float)p.res;
  pos[i] = ((float)x + lgn_rand01(p.seed, p.iteration, cell, 0u)) * inv;
  pos[p.stride + i] = ((float)y + lgn_rand01(p.seed, p.iteration, cell, 1u)) * inv;
  pos[2u * p.stride + i] = ((float)z + lgn_rand01(p.seed, p.iteration, cell, 2u)) * inv;
}
