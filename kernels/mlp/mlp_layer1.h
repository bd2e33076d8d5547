// OpenCL-only: one dense layer for one sample, y[j] = act(sum_k W[j][k] x[k]) for j < out, four
// outputs per pass over the inputs (four independent FMA chains in flight, each summed in input
// order as the CPU chain's float16 lanes are). OpenCL C 1.2 has no generic address space, so the
// body is written once and stamped per placement of the weights and activations: global rows of
// stride s for the per-sample GPU chain (mlp_chain_per_sample.cl), local weights and private
// activations (stride 1, registers) for the fused marcher (march/march_fused_field.h).
#pragma once
#include "mlp/mlp_types.h"

// NAME(W, in, out, act, x, sx, y, sy): in and out multiples of 4; x[k * sx], y[j * sy].
#define LGN_DEFINE_MLP_LAYER_FORWARD1(NAME, W_SPACE, X_SPACE, Y_SPACE)                                   \
  inline void NAME(W_SPACE const float* restrict W, uint in, uint out, uint act, X_SPACE const float* x, \
                   uint sx, Y_SPACE float* y, uint sy) {                                                 \
    for (uint j = 0; j < out; j += 4) {                                                                  \
      W_SPACE const float* w = W + j * in;                                                               \
      float a0 = 0.0f, a1 = 0.0f, a2 = 0.0f, a3 = 0.0f;                                                  \
      for (uint k = 0; k < in; ++k) {                                                                    \
        const float xk = x[k * sx];                                                                      \
        a0 = fma(w[k], xk, a0);                                                                          \
        a1 = fma(w[in + k], xk, a1);                                                                     \
        a2 = fma(w[2 * in + k], xk, a2);                                                                 \
        a3 = fma(w[3 * in + k], xk, a3);                                                                 \
      }                                                                                                  \
      y[j * sy] = lgn_activate(a0, act);                                                                 \
      y[(j + 1) * sy] = lgn_activate(a1, act);                                                           \
      y[(j + 2) * sy] = lgn_activate(a2, act);                                                           \
      y[(j + 3) * sy] = lgn_activate(a3, act);                                                           \
    }                                                                                                    \
  }
