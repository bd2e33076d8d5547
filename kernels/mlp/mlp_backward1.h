// OpenCL-only: the backward pass of the fused MLP chain for one sample (the per-sample GPU chains):
// one dense layer's input delta, the sigmoid RGB output's delta and the density head's term. The
// layer body is stamped per placement of the weights and activations (OpenCL C 1.2 has no generic
// address space), like the forward in mlp_layer1.h.
#pragma once
#include "mlp/mlp_types.h"

// NAME(W, in, out, k_begin, relu, dy, sdy, x, sx, dx, sdx): dx[k] = (sum_j W[j][k] dy[j]) * (relu ?
// x[k] > 0 : 1) for k_begin <= k < in (both multiples of 4), summed over j in order.
#define LGN_DEFINE_MLP_LAYER_BACKWARD1(NAME, W_SPACE, D_SPACE, X_SPACE)                                   \
  inline void NAME(W_SPACE const float* restrict W, uint in, uint out, uint k_begin, uint relu,           \
                   D_SPACE const float* dy, uint sdy, X_SPACE const float* x, uint sx, D_SPACE float* dx, \
                   uint sdx) {                                                                            \
    for (uint k = k_begin; k < in; k += 4) {                                                              \
      float a0 = 0.0f, a1 = 0.0f, a2 = 0.0f, a3 = 0.0f;                                                   \
      for (uint j = 0; j < out; ++j) {                                                                    \
        const float d = dy[j * sdy];                                                                      \
        W_SPACE const float* wj = W + j * in + k;                                                         \
        a0 = fma(wj[0], d, a0);                                                                           \
        a1 = fma(wj[1], d, a1);                                                                           \
        a2 = fma(wj[2], d, a2);                                                                           \
        a3 = fma(wj[3], d, a3);                                                                           \
      }                                                                                                   \
      const float a[4] = {a0, a1, a2, a3};                                                                \
      for (uint q = 0; q < 4; ++q) dx[(k + q) * sdx] = (!relu || x[(k + q) * sx] > 0.0f) ? a[q] : 0.0f;   \
    }                                                                                                     \
  }

// The last layer's output delta for sample i: sigmoid backward of dL/drgb (row 3 is padding; zeros
// for the padded samples, valid = 0).
inline void mlp_rgb_output_delta(const MlpChainParams* p, __global const float* acts, __global float* deltas,
                                 __global const float* restrict d_rgb, uint i, int valid) {
  const uint s = p->stride;
  for (uint c = 0; c < 4; ++c) {
    float d = 0.0f;
    if (c < 3 && valid) d = lgn_sigmoid_backward(d_rgb[c * s + i], acts[(p->rgb_row + c) * s + i]);
    deltas[(p->dy_row[p->layers - 1] + c) * s + i] = d;
  }
}

// After layer l = geo_layer's input delta: the raw density's delta gets dL/dsigma * dsigma/draw
// added to the colour network's share.
inline void mlp_add_sigma_delta(const MlpChainParams* p, __global const float* acts, __global float* deltas,
                                __global const float* restrict d_sigma, uint l, uint i) {
  const uint s = p->stride;
  const float raw = acts[p->raw_row * s + i];
  deltas[p->dy_row[l - 1] * s + i] += d_sigma[i] * lgn_sigma_grad(raw, lgn_sigma_from_raw(raw));
}
