// The occupancy grid's indexing rule, shared by the training sampler, the trainer's host code and
// the inference marcher: a res^3 grid of cells over the model's AABB in normalised coordinates
// [0,1)^3, cell index x + res*(y + res*z), one bit per cell in 32-bit words (bit cell&31 of word
// cell>>5). Also the distance to a cell's exit, used to jump over empty cells.
#pragma once
#include "common/cl_compat.h"

// Number of 32-bit words of a res^3 bitfield.
LGN_INLINE lgn_uint occ_word_count(lgn_uint res) { return (res * res * res + 31u) / 32u; }

// Cell of a normalised position, or -1 outside [0,1)^3 (NaN positions are outside too).
LGN_INLINE lgn_int occ_cell_index(lgn_uint res, float x, float y, float z) {
  if (!(x >= 0.0f && x < 1.0f && y >= 0.0f && y < 1.0f && z >= 0.0f && z < 1.0f)) return -1;
  lgn_uint ix = (lgn_uint)(x * (float)res), iy = (lgn_uint)(y * (float)res), iz = (lgn_uint)(z * (float)res);
  ix = ix < res ? ix : res - 1u;
  iy = iy < res ? iy : res - 1u;
  iz = iz < res ? iz : res - 1u;
  return (lgn_int)(ix + res * (iy + res * iz));
}

// Whether a cell is occupied (cells outside the grid are empty).
LGN_INLINE int occ_cell_occupied(LGN_GLOBAL const lgn_uint* bits, lgn_int cell) {
  if (cell < 0) return 0;
  return (int)((bits[(lgn_uint)cell >> 5] >> ((lgn_uint)cell & 31u)) & 1u);
}

LGN_INLINE int occ_test(LGN_GLOBAL const lgn_uint* bits, lgn_uint res, float x, float y, float z) {
  return occ_cell_occupied(bits, occ_cell_index(res, x, y, z));
}

// Distance to the exit of the cell around normalised position p along the ray p + s*d, where d is
// the ray direction in normalised units per ray parameter (world direction / AABB extent), so the
// result is in the caller's ray-parameter units. Returns a huge value when d is 0 on every axis.
LGN_INLINE float occ_axis_exit(lgn_uint res, float p, float d) {
  float r = (float)res;
  float c = floor(p * r);
  if (d > 0.0f) return ((c + 1.0f) / r - p) / d;
  if (d < 0.0f) return (c / r - p) / d;
  return 3.0e38f;
}

LGN_INLINE float occ_cell_exit(lgn_uint res, float px, float py, float pz, float dx, float dy, float dz) {
  float t = occ_axis_exit(res, px, dx);
  t = fmin(t, occ_axis_exit(res, py, dy));
  t = fmin(t, occ_axis_exit(res, pz, dz));
  return fmax(t, 0.0f);
}
