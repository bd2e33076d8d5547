// OpenCL-only: the field evaluated for one sample inside the fused marcher (march_fused.cl), from
// the same shared math as the batch kernels: the analytic primitives (march_math.h), or the NeRF
// forward pass, i.e. the hash encoding of every level (hashgrid_interpolate, hashgrid_types.h),
// the density MLP, sigma = exp(min(raw, 15)), the SH basis of the direction and the colour MLP
// (lgn_activate, lgn_sigma_from_raw, sh_basis: mlp_types.h; the layer body: mlp_layer1.h). Every
// activation is a private array whose size is a compile-time define, so a GPU keeps it in registers;
// the weights come from local memory (staged once per work-group) or, when they do not fit, global.
#pragma once
#include "march/march_fused_types.h"
#include "march/march_math.h"

#if LGN_FUSED_FIELD == LGN_FUSED_NERF
#include "mlp/mlp_layer1.h"

#if LGN_FUSED_LOCAL_WEIGHTS
#define LGN_FUSED_W_SPACE __local
#else
#define LGN_FUSED_W_SPACE __global
#endif
// Weights in local (or global) memory, activations private with stride 1.
LGN_DEFINE_MLP_LAYER_FORWARD1(fused_layer, LGN_FUSED_W_SPACE, , )

#define LGN_FUSED_COLOR_IN (LGN_FUSED_SH_PAD + LGN_FUSED_GEO)

// sigma and rgb of the NeRF at pos (normalised to the box) seen along the unit direction d.
inline void fused_nerf_eval(__constant const MarchFusedField* f, __global const float* params,
                            LGN_FUSED_W_SPACE const float* W, const float* pos, const float* d, float* sigma,
                            float* rgb) {
  float enc[LGN_FUSED_ENC];
  for (uint l = 0; l < LGN_FUSED_LEVELS; ++l) {
    const uint res = f->hash.resolution[l], size = f->hash.size[l], dense = f->hash.dense[l];
    uint cell[3];
    float frac[3];
    hashgrid_cell(res, pos[0], pos[1], pos[2], cell, frac);
    __global const float* table = params + f->hash.offset[l];
    for (uint c = 0; c < LGN_FUSED_FEATURES; ++c)
      enc[l * LGN_FUSED_FEATURES + c] = hashgrid_interpolate(table + c * size, res, size, dense, cell, frac);
  }
  for (uint k = LGN_FUSED_LEVELS * LGN_FUSED_FEATURES; k < LGN_FUSED_ENC; ++k) enc[k] = 0.0f;
  float hidden[LGN_FUSED_DENSITY_HIDDEN];
  fused_layer(W + f->mlp.w_offset[0], LGN_FUSED_ENC, LGN_FUSED_DENSITY_HIDDEN, f->mlp.act[0], enc, 1, hidden,
              1);
  // The colour network's input: SH of the direction, then the geometry features (raw density first).
  float color_in[LGN_FUSED_COLOR_IN];
  for (uint k = 0; k < LGN_FUSED_SH_PAD; ++k) color_in[k] = 0.0f;
  sh_basis(d[0], d[1], d[2], LGN_FUSED_SH_DEGREE, color_in);
  fused_layer(W + f->mlp.w_offset[1], LGN_FUSED_DENSITY_HIDDEN, LGN_FUSED_GEO, f->mlp.act[1], hidden, 1,
              color_in + LGN_FUSED_SH_PAD, 1);
  *sigma = lgn_sigma_from_raw(color_in[LGN_FUSED_SH_PAD]);
  float a[LGN_FUSED_COLOR_HIDDEN], b[LGN_FUSED_COLOR_HIDDEN];
  fused_layer(W + f->mlp.w_offset[2], LGN_FUSED_COLOR_IN, LGN_FUSED_COLOR_HIDDEN, f->mlp.act[2], color_in, 1,
              a, 1);
  // Hidden colour layers ping-pong between a and b; the last writes the 3 sigmoid outputs (+ padding).
  for (uint h = 1; h + 1 < LGN_FUSED_COLOR_LAYERS; ++h) {
    if (h & 1u)
      fused_layer(W + f->mlp.w_offset[2 + h], LGN_FUSED_COLOR_HIDDEN, LGN_FUSED_COLOR_HIDDEN,
                  f->mlp.act[2 + h], a, 1, b, 1);
    else
      fused_layer(W + f->mlp.w_offset[2 + h], LGN_FUSED_COLOR_HIDDEN, LGN_FUSED_COLOR_HIDDEN,
                  f->mlp.act[2 + h], b, 1, a, 1);
  }
  const uint last = LGN_FUSED_COLOR_LAYERS - 1;
  float out[4];
  fused_layer(W + f->mlp.w_offset[2 + last], LGN_FUSED_COLOR_HIDDEN, 4, f->mlp.act[2 + last],
              (last & 1u) ? a : b, 1, out, 1);
  rgb[0] = out[0];
  rgb[1] = out[1];
  rgb[2] = out[2];
}
#endif

// The field of this program at pos (normalised to the box) along the unit direction d.
inline void fused_field_eval(__constant const MarchFusedField* f, const AnalyticFieldParams* analytic,
                             __global const float* params, __local const float* local_weights,
                             const float* pos, const float* d, float* sigma, float* rgb) {
#if LGN_FUSED_FIELD == LGN_FUSED_NERF
#if LGN_FUSED_LOCAL_WEIGHTS
  fused_nerf_eval(f, params, local_weights, pos, d, sigma, rgb);
#else
  fused_nerf_eval(f, params, params + f->mlp_begin, pos, d, sigma, rgb);
#endif
#else
  analytic_eval_normalised(analytic, pos, sigma, rgb);
#endif
}
