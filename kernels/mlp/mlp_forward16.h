// OpenCL-only: the CPU dense-layer forward body (32 samples per call in two float16 halves; see
// mlp_block.h), written once and stamped per placement of the activations, because OpenCL C 1.2 has
// no generic address space: global rows for the layer and chain kernels (mlp_block.h), work-group
// local rows for the field's fused inference (kernels/field/field_infer.cl). Uses MLP_FMA8,
// MLP_STORE8 and MLP_ZERO4 from mlp_block.h.
#pragma once

// NAME(W, in, out, act, xb, yb, s, i0, n16): y[j] = act(sum_k W[j][k] x[k]) for j < out, rows of
// stride s from xb / yb (at sample i0 of n16); W points at the layer's first weight.
#define LGN_DEFINE_MLP_LAYER_FORWARD16(NAME, X_SPACE, Y_SPACE)                                          \
  inline void NAME(__global const float* restrict W, uint in, uint out, uint act,                       \
                   X_SPACE const float* restrict xb, Y_SPACE float* restrict yb, uint s, uint i0,       \
                   uint n16) {                                                                          \
    uint j = 0;                                                                                         \
    if (i0 + 16 < n16) {                                                                                \
      for (; j + 8 <= out; j += 8) {                                                                    \
        __global const float* w = W + j * in;                                                           \
        float16 a0 = 0.0f, a1 = 0.0f, a2 = 0.0f, a3 = 0.0f, a4 = 0.0f, a5 = 0.0f, a6 = 0.0f, a7 = 0.0f; \
        float16 b0 = 0.0f, b1 = 0.0f, b2 = 0.0f, b3 = 0.0f, b4 = 0.0f, b5 = 0.0f, b6 = 0.0f, b7 = 0.0f; \
        for (uint k = 0; k < in; ++k) {                                                                 \
          const float16 xa = vload16(0, xb + k * s), xc = vload16(0, xb + k * s + 16);                  \
          MLP_FMA8(a, xa, w, in, k);                                                                    \
          MLP_FMA8(b, xc, w, in, k);                                                                    \
        }                                                                                               \
        MLP_STORE8(a, yb + j * s, s, act);                                                              \
        MLP_STORE8(b, yb + j * s + 16, s, act);                                                         \
      }                                                                                                 \
    }                                                                                                   \
    for (uint h16 = 0; h16 < 32 && i0 + h16 < n16; h16 += 16) {                                         \
      for (uint jj = j; jj < out; jj += 4) {                                                            \
        __global const float* w = W + jj * in;                                                          \
        MLP_ZERO4;                                                                                      \
        for (uint k = 0; k < in; ++k) {                                                                 \
          const float16 xv = vload16(0, xb + k * s + h16);                                              \
          a0 = fma((float16)(w[k]), xv, a0);                                                            \
          a1 = fma((float16)(w[in + k]), xv, a1);                                                       \
          a2 = fma((float16)(w[2 * in + k]), xv, a2);                                                   \
          a3 = fma((float16)(w[3 * in + k]), xv, a3);                                                   \
        }                                                                                               \
        Y_SPACE float* o = yb + jj * s + h16;                                                           \
        vstore16(lgn_activate16(a0, act), 0, o);                                                        \
        vstore16(lgn_activate16(a1, act), 0, o + s);                                                    \
        vstore16(lgn_activate16(a2, act), 0, o + 2 * s);                                                \
        vstore16(lgn_activate16(a3, act), 0, o + 3 * s);                                                \
      }                                                                                                 \
    }                                                                                                   \
  }
