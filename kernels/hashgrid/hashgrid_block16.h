// OpenCL-only: the CPU hash-encoding helpers for 16 samples in float16/uint16 lanes (cell, corner
// entries and weights, table gathers), shared by the encoding kernels (hashgrid.cl) and the fused
// inference of the field (kernels/field/field_infer.cl), so both compute the same values bit for bit.
#pragma once
#include "hashgrid/hashgrid_types.h"

inline float16 hashgrid_gather16(__global const float* t, uint16 i) {
  return (float16)(t[i.s0], t[i.s1], t[i.s2], t[i.s3], t[i.s4], t[i.s5], t[i.s6], t[i.s7], t[i.s8], t[i.s9],
                   t[i.sa], t[i.sb], t[i.sc], t[i.sd], t[i.se], t[i.sf]);
}

// Cell (uint16 per axis) and fractional position (float16 per axis) of 16 samples on one level.
typedef struct HashCell16 {
  uint16 x, y, z;
  float16 fx, fy, fz;
} HashCell16;

inline HashCell16 hashgrid_cell16(__global const float* pos, uint stride, uint i0, uint res) {
  const float res_f = (float)res;
  const float16 px = LGN_HASH_GRID_POS(vload16(0, pos + i0), res_f);
  const float16 py = LGN_HASH_GRID_POS(vload16(0, pos + stride + i0), res_f);
  const float16 pz = LGN_HASH_GRID_POS(vload16(0, pos + 2 * stride + i0), res_f);
  const float16 cx = LGN_HASH_CELL_OF(px, res_f), cy = LGN_HASH_CELL_OF(py, res_f),
                cz = LGN_HASH_CELL_OF(pz, res_f);
  HashCell16 h;
  h.x = convert_uint16(cx);
  h.y = convert_uint16(cy);
  h.z = convert_uint16(cz);
  h.fx = px - cx;
  h.fy = py - cy;
  h.fz = pz - cz;
  return h;
}

// Entry and trilinear weight of corner c (bit 0 = x, 1 = y, 2 = z) for 16 samples.
inline uint16 hashgrid_corner16(const HashCell16* h, uint c, uint res, uint size, uint dense, float16* w) {
  const uint bx = c & 1u, by = (c >> 1) & 1u, bz = (c >> 2) & 1u;
  *w = (bx ? h->fx : 1.0f - h->fx) * (by ? h->fy : 1.0f - h->fy) * (bz ? h->fz : 1.0f - h->fz);
  const uint16 x = h->x + bx, y = h->y + by, z = h->z + bz;
  if (dense) return LGN_HASH_DENSE_INDEX(res + 1u, x, y, z);
  return LGN_HASH_SPATIAL_INDEX(size - 1u, x, y, z);
}

// Features f0 and f0 + 1 (when `two`) of one level for the 16 samples of cell h: trilinear over the 8
// corners, in corner order. `table` is the level's table (feature-major, `size` entries per feature).
inline void hashgrid_interp_pair16(const HashCell16* h, __global const float* table, uint f0, uint two,
                                   uint res, uint size, uint dense, float16* a0, float16* a1) {
  float16 s0 = 0.0f, s1 = 0.0f;
  for (uint c = 0; c < 8; ++c) {
    float16 w;
    const uint16 e = hashgrid_corner16(h, c, res, size, dense, &w);
    s0 = fma(w, hashgrid_gather16(table + f0 * size, e), s0);
    if (two) s1 = fma(w, hashgrid_gather16(table + (f0 + 1) * size, e), s1);
  }
  *a0 = s0;
  *a1 = s1;
}
