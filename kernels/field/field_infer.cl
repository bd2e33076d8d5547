// The field's fused inference on CPUs: one work-item takes 32 samples through the hash encoding,
// the SH encoding of their directions, the density and colour MLPs and the density head, with the
// activations in its work-group's local scratch (FieldInferParams.rows x 32 floats, hot in L1/L2
// from one slab to the next) instead of [row][max_batch] global buffers. It calls the same helpers
// as the layered kernels (hashgrid_block16.h, mlp_forward16.h, sh_basis16, lgn_sigma_from_raw) in the
// same order, so sigma and rgb equal the layered forward's bit for bit (tests/host/field).
#include "field/field_infer_types.h"
#include "hashgrid/hashgrid_block16.h"
#include "mlp/mlp_block.h"

LGN_DEFINE_MLP_LAYER_FORWARD16(field_layer_forward_local, __local, __local)

// Encoding rows of level l for the 16 samples from i into x (row stride LGN_INFER_SLAB); zeros past n.
inline void field_encode_level16(const FieldInferParams* p, __global const float* restrict W,
                                 __global const float* restrict pos, uint i, uint l, __local float* x) {
  const HashgridParams* q = &p->hash;
  const uint F = q->features, res = q->resolution[l], size = q->size[l], dense = q->dense[l];
  const int16 valid = (int16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15) + (int)i < (int)q->n;
  const HashCell16 h = hashgrid_cell16(pos, q->stride, i, res);
  __global const float* table = W + q->offset[l];
  for (uint f0 = 0; f0 < F; f0 += 2) {
    const uint two = f0 + 1 < F;
    float16 a0, a1;
    hashgrid_interp_pair16(&h, table, f0, two, res, size, dense, &a0, &a1);
    vstore16(select((float16)(0.0f), a0, valid), 0, x + (l * F + f0) * LGN_INFER_SLAB);
    if (two) vstore16(select((float16)(0.0f), a1, valid), 0, x + (l * F + f0 + 1) * LGN_INFER_SLAB);
  }
}

// SH rows of the 16 samples from i into x (zeros past n and in the padding rows).
inline void field_sh16(const FieldInferParams* p, __global const float* restrict dir, uint i,
                       __local float* x) {
  const uint S = p->hash.stride;
  const int16 valid = (int16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15) + (int)i < (int)p->hash.n;
  float16 sh[16];
  for (int c = 0; c < 16; ++c) sh[c] = 0.0f;
  sh_basis16(vload16(0, dir + i), vload16(0, dir + S + i), vload16(0, dir + 2 * S + i), p->sh_degree, sh);
  for (uint c = 0; c < p->sh_pad; ++c)
    vstore16(c < p->sh_count ? select((float16)(0.0f), sh[c], valid) : (float16)(0.0f), 0,
             x + (p->sh_row + c) * LGN_INFER_SLAB);
}

// Global size: n16 / 32 rounded up, times the group size; local scratch: group size x rows x 32 floats.
__kernel void field_infer(const FieldInferParams p, __global const float* restrict W,
                          __global const float* restrict pos, __global const float* restrict dir,
                          __global float* restrict sigma, __global float* restrict rgb,
                          __local float* scratch) {
  const uint i0 = get_global_id(0) * LGN_INFER_SLAB;
  __local float* x = scratch + get_local_id(0) * p.rows * LGN_INFER_SLAB;
  // Level by level across the group (the barrier makes PoCL run every work-item's level l before
  // level l + 1), so a level's table lines serve the group's 256 neighbouring samples in turn.
  for (uint l = 0; l < p.hash.levels; ++l) {
    for (uint h = 0; h < LGN_INFER_SLAB && i0 + h < p.n16; h += 16)
      field_encode_level16(&p, W, pos, i0 + h, l, x + h);
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (i0 >= p.n16) return;
  for (uint r = p.hash.levels * p.hash.features; r < p.enc_rows; ++r)
    for (uint h = 0; h < LGN_INFER_SLAB; h += 16) vstore16((float16)(0.0f), 0, x + r * LGN_INFER_SLAB + h);
  for (uint h = 0; h < LGN_INFER_SLAB && i0 + h < p.n16; h += 16) field_sh16(&p, dir, i0 + h, x + h);
  for (uint l = 0; l < p.layers; ++l)
    field_layer_forward_local(W + p.w_offset[l], p.in[l], p.out[l], p.act[l], x + p.x_row[l] * LGN_INFER_SLAB,
                              x + p.y_row[l] * LGN_INFER_SLAB, LGN_INFER_SLAB, i0, p.n16);
  const uint S = p.hash.stride;
  for (uint k = 0; k < LGN_INFER_SLAB && i0 + k < p.hash.n; ++k) {
    const uint i = i0 + k;
    sigma[i] = lgn_sigma_from_raw(x[p.raw_row * LGN_INFER_SLAB + k]);
    for (uint c = 0; c < 3; ++c) rgb[c * S + i] = x[(p.rgb_row + c) * LGN_INFER_SLAB + k];
  }
}
