// Parameters of the multiresolution hash encoding kernels (Instant-NGP) and the index/weight math
// shared by the kernels and the host reference: the host build is the oracle for the kernels.
// Table layout is planar [level][feature][entry]; the encoding output is structure-of-arrays
// enc[(level * features + feature) * stride + sample].
#pragma once
#include "common/cl_compat.h"

#define LGN_HASH_MAX_LEVELS 32
#define LGN_HASH_PRIME_Y 2654435761u
#define LGN_HASH_PRIME_Z 805459861u

typedef struct HashgridParams {
  lgn_uint n;       // samples
  lgn_uint stride;  // row stride of positions / encodings (max_batch)
  lgn_uint levels;
  lgn_uint features;                         // per level
  lgn_uint resolution[LGN_HASH_MAX_LEVELS];  // cells per axis
  lgn_uint size[LGN_HASH_MAX_LEVELS];        // entries per feature
  lgn_uint dense[LGN_HASH_MAX_LEVELS];       // 1: direct index, 0: hashed (size is a power of 2)
  lgn_uint offset[LGN_HASH_MAX_LEVELS];      // first parameter of the level
} HashgridParams;

LGN_STATIC_ASSERT(sizeof(HashgridParams) == 16 + 4 * 4 * LGN_HASH_MAX_LEVELS, "HashgridParams layout");

// The index and cell math is written once as macros valid for scalars (host reference, GPU
// kernels) and OpenCL vectors (the CPU kernels process 16 samples per work-item in uint16/float16).
// Table entry of grid vertex (x, y, z) on a dense level (vertices per axis v = res + 1) and on a
// hashed level (the Instant-NGP spatial hash: XOR of coordinates times large primes, masked).
#define LGN_HASH_DENSE_INDEX(v, x, y, z) ((x) + (v) * ((y) + (v) * (z)))
#define LGN_HASH_SPATIAL_INDEX(mask, x, y, z) \
  (((x) ^ ((y)*LGN_HASH_PRIME_Y) ^ ((z)*LGN_HASH_PRIME_Z)) & (mask))
// Grid coordinate of p in [0,1] (clamped; NaN maps to 0) on a level of res_f cells, and the
// cell's lower corner (as a float, at most res - 1). frac = pos - cell.
#define LGN_HASH_GRID_POS(p, res_f) (fmin(fmax((p), 0.0f), 1.0f) * (res_f))
#define LGN_HASH_CELL_OF(pos, res_f) fmin(floor(pos), (res_f)-1.0f)

LGN_INLINE lgn_uint hashgrid_index(lgn_uint res, lgn_uint size, lgn_uint dense, lgn_uint x, lgn_uint y,
                                   lgn_uint z) {
  if (dense) return LGN_HASH_DENSE_INDEX(res + 1u, x, y, z);
  return LGN_HASH_SPATIAL_INDEX(size - 1u, x, y, z);
}

// The cell containing p in [0,1]^3 and the fractional position in it.
LGN_INLINE void hashgrid_cell(lgn_uint res, float px, float py, float pz, lgn_uint* cell, float* frac) {
  float p[3];
  p[0] = px;
  p[1] = py;
  p[2] = pz;
  const float res_f = (float)res;
  for (int d = 0; d < 3; ++d) {
    float x = LGN_HASH_GRID_POS(p[d], res_f);
    float c = LGN_HASH_CELL_OF(x, res_f);
    cell[d] = (lgn_uint)c;
    frac[d] = x - c;
  }
}

// Corner c (bit 0 = x, bit 1 = y, bit 2 = z) of the cell: its table entry and trilinear weight.
LGN_INLINE lgn_uint hashgrid_corner(lgn_uint res, lgn_uint size, lgn_uint dense, const lgn_uint* cell,
                                    const float* frac, lgn_uint c, float* weight) {
  float w = 1.0f;
  lgn_uint v[3];
  for (int d = 0; d < 3; ++d) {
    lgn_uint bit = (c >> d) & 1u;
    v[d] = cell[d] + bit;
    w *= bit ? frac[d] : 1.0f - frac[d];
  }
  *weight = w;
  return hashgrid_index(res, size, dense, v[0], v[1], v[2]);
}

// One feature of one level at the point whose cell and fraction hashgrid_cell gave: the trilinear
// blend of the feature's table entries at the 8 corners (table points at the feature's entry 0), in
// corner order with fused multiply-adds as the CPU kernel's float16 lanes do. The GPU encoding and the
// fused marcher (kernels/march/march_fused_field.h) both call it.
LGN_INLINE float hashgrid_interpolate(LGN_GLOBAL const float* table, lgn_uint res, lgn_uint size,
                                      lgn_uint dense, const lgn_uint* cell, const float* frac) {
  float acc = 0.0f;
  for (lgn_uint c = 0; c < 8u; ++c) {
    float w;
    const lgn_uint e = hashgrid_corner(res, size, dense, cell, frac, c, &w);
    acc = fma(w, table[e], acc);
  }
  return acc;
}
