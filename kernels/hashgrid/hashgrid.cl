// Multiresolution hash encoding, forward and backward. On CPUs one work-item handles 16 samples of
// one level in float16/uint16 vectors (PoCL does not vectorise across work-items whose bodies
// branch or loop); the table reads are gathers. Backward is deterministic and free of float
// atomics: one work-item per level (CPU) or per (level, feature) (GPU variant) owns that slice of
// the gradient table and scans the samples in order. On GPUs the forward runs one work-item per
// (sample, level) and the optional non-deterministic backward uses a float atomic add (the
// hardware's on NVIDIA, else compare-and-swap).
#include "hashgrid/hashgrid_block16.h"

// The variant follows the device type unless the host forces one (tests run both on a CPU).
#ifndef LGN_HASHGRID_GPU
#define LGN_HASHGRID_GPU LGN_DEVICE_GPU
#endif

#if !LGN_HASHGRID_GPU
// Global size: (n16 / 16, levels). Padded samples n..n16 get zeros.
__kernel void hashgrid_encode(const HashgridParams p, __global const float* restrict params,
                              __global const float* restrict pos, __global float* restrict enc) {
  const uint i0 = get_global_id(0) * 16;
  const uint l = get_global_id(1);
  if (i0 >= p.stride || l >= p.levels) return;
  const uint F = p.features, res = p.resolution[l], size = p.size[l], dense = p.dense[l];
  const HashCell16 h = hashgrid_cell16(pos, p.stride, i0, res);
  __global const float* table = params + p.offset[l];
  const int16 valid = (int16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15) + (int)i0 < (int)p.n;
  for (uint f0 = 0; f0 < F; f0 += 2) {
    const uint two = f0 + 1 < F;
    float16 a0, a1;
    hashgrid_interp_pair16(&h, table, f0, two, res, size, dense, &a0, &a1);
    vstore16(select((float16)(0.0f), a0, valid), 0, enc + (l * F + f0) * p.stride + i0);
    if (two) vstore16(select((float16)(0.0f), a1, valid), 0, enc + (l * F + f0 + 1) * p.stride + i0);
  }
}

// Adds g[k] to table[e[k]] for the first `lanes` lanes, in lane order.
inline void hashgrid_scatter16(__global float* table, uint16 e, float16 g, uint lanes) {
  uint ev[16];
  float gv[16];
  vstore16(e, 0, ev);
  vstore16(g, 0, gv);
  for (uint k = 0; k < lanes; ++k) table[ev[k]] += gv[k];
}

// grads must hold zeros for the hash part before the launch. One work-item per level owns that
// level's gradient tables and scans the samples in order, so every entry sees its additions in
// sample order whatever the scheduling. (Splitting a level's entries among several work-items
// that each scan all samples was 3x slower on PoCL: the per-lane range test mispredicts.)
// Global size: levels.
__kernel void hashgrid_backward(const HashgridParams p, __global const float* restrict pos,
                                __global const float* restrict d_enc, __global float* restrict grads) {
  const uint l = get_global_id(0);
  if (l >= p.levels) return;
  const uint F = p.features, res = p.resolution[l], size = p.size[l], dense = p.dense[l];
  __global float* table = grads + p.offset[l];
  __global const float* d = d_enc + l * F * p.stride;
  for (uint i0 = 0; i0 < p.n; i0 += 16) {
    const HashCell16 h = hashgrid_cell16(pos, p.stride, i0, res);
    const uint lanes = min(16u, p.n - i0);
    for (uint c = 0; c < 8; ++c) {
      float16 w;
      const uint16 e = hashgrid_corner16(&h, c, res, size, dense, &w);
      for (uint f = 0; f < F; ++f)
        hashgrid_scatter16(table + f * size, e, w * vload16(0, d + f * p.stride + i0), lanes);
    }
  }
}
#else
// Global size: (n16, levels).
__kernel void hashgrid_encode(const HashgridParams p, __global const float* restrict params,
                              __global const float* restrict pos, __global float* restrict enc) {
  const uint i = get_global_id(0);
  const uint l = get_global_id(1);
  if (i >= p.stride || l >= p.levels) return;
  const uint F = p.features;
  if (i >= p.n) {
    for (uint f = 0; f < F; ++f) enc[(l * F + f) * p.stride + i] = 0.0f;
    return;
  }
  const uint res = p.resolution[l], size = p.size[l], dense = p.dense[l];
  uint cell[3];
  float frac[3];
  hashgrid_cell(res, pos[i], pos[p.stride + i], pos[2 * p.stride + i], cell, frac);
  __global const float* table = params + p.offset[l];
  for (uint f = 0; f < F; ++f)
    enc[(l * F + f) * p.stride + i] = hashgrid_interpolate(table + f * size, res, size, dense, cell, frac);
}

// Deterministic GPU backward: one work-item per (level, feature) scanning the samples in order.
__kernel void hashgrid_backward(const HashgridParams p, __global const float* restrict pos,
                                __global const float* restrict d_enc, __global float* restrict grads) {
  const uint l = get_global_id(0) / p.features, f = get_global_id(0) % p.features;
  if (l >= p.levels) return;
  const uint res = p.resolution[l], size = p.size[l], dense = p.dense[l];
  __global float* table = grads + p.offset[l] + f * size;
  for (uint i = 0; i < p.n; ++i) {
    uint cell[3];
    float frac[3];
    hashgrid_cell(res, pos[i], pos[p.stride + i], pos[2 * p.stride + i], cell, frac);
    const float d = d_enc[(l * p.features + f) * p.stride + i];
    for (uint c = 0; c < 8; ++c) {
      float w;
      uint e = hashgrid_corner(res, size, dense, cell, frac, c, &w);
      table[e] += w * d;
    }
  }
}

#ifndef LGN_FLOAT_ADD_PTX
#define LGN_FLOAT_ADD_PTX 0
#endif

// Float add to global memory from many work-items. NVIDIA (-DLGN_FLOAT_ADD_PTX=1, host/cl/runtime.h):
// the hardware's reduction, resolved in L2 without a read back; elsewhere a compare-and-swap loop,
// which retries under contention (the coarse levels, where every sample of a batch meets a few
// hundred entries).
inline void hashgrid_atomic_add(volatile __global float* addr, float v) {
#if LGN_FLOAT_ADD_PTX
  __asm__ __volatile__("red.global.add.f32 [%0], %1;" : : "l"(addr), "f"(v) : "memory");
#else
  union {
    uint u;
    float f;
  } old, next;
  do {
    old.f = *addr;
    next.f = old.f + v;
  } while (atomic_cmpxchg((volatile __global uint*)addr, old.u, next.u) != old.u);
#endif
}

// Non-deterministic GPU path: one work-item per (sample, level), CAS float adds.
__kernel void hashgrid_backward_atomic(const HashgridParams p, __global const float* restrict pos,
                                       __global const float* restrict d_enc, __global float* grads) {
  const uint i = get_global_id(0);
  const uint l = get_global_id(1);
  if (i >= p.n || l >= p.levels) return;
  const uint F = p.features;
  const uint res = p.resolution[l], size = p.size[l], dense = p.dense[l];
  uint cell[3];
  float frac[3];
  hashgrid_cell(res, pos[i], pos[p.stride + i], pos[2 * p.stride + i], cell, frac);
  __global float* table = grads + p.offset[l];
  for (uint c = 0; c < 8; ++c) {
    float w;
    uint e = hashgrid_corner(res, size, dense, cell, frac, c, &w);
    for (uint f = 0; f < F; ++f)
      hashgrid_atomic_add(table + f * size + e, w * d_enc[(l * F + f) * p.stride + i]);
  }
}
#endif
