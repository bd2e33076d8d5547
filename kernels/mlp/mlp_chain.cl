// Fused MLP chains: one work-item runs every layer of the network on its 32 samples, so each
// layer reads the previous layer's output from cache instead of memory (at 2^16 samples the
// layer-by-layer kernels were memory bound at about half the in-cache FLOP rate). Forward: the
// layers in order. Backward (input deltas only; weight gradients are the separate deterministic
// chunked reduction of mlp.cl): the RGB output delta, the layers in reverse, and the sigma term
// added to the raw-density delta once the colour network's input delta exists.
#include "mlp/mlp_block.h"

// Global size: n16 / 16 rounded up to n32 / 32.
__kernel void mlp_chain_forward(const MlpChainParams p, __global const float* restrict W,
                                __global float* acts) {
  const uint i0 = get_global_id(0) * 32;
  if (i0 >= p.n16) return;
  const uint s = p.stride;
  for (uint l = 0; l < p.layers; ++l)
    mlp_layer_forward(W + p.w_offset[l], p.in[l], p.out[l], p.act[l], acts + p.x_row[l] * s + i0,
                      acts + p.y_row[l] * s + i0, s, i0, p.n16);
}

inline int16 mlp_valid16(uint i, uint n) {
  return (int16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15) + (int)i < (int)n;
}

// Global size as mlp_chain_forward. d_sigma: n values; d_rgb: 3 rows of stride.
__kernel void mlp_chain_backward(const MlpChainParams p, __global const float* restrict W,
                                 __global const float* acts, __global float* deltas,
                                 __global const float* restrict d_sigma,
                                 __global const float* restrict d_rgb) {
  const uint i0 = get_global_id(0) * 32;
  if (i0 >= p.n16) return;
  const uint s = p.stride, last = p.layers - 1;
  for (uint i = i0; i < i0 + 32 && i < p.n16; i += 16) {
    const int16 valid = mlp_valid16(i, p.n);
    for (uint c = 0; c < 4; ++c) {
      float16 d = 0.0f;
      if (c < 3) {
        const float16 r = vload16(0, acts + (p.rgb_row + c) * s + i);
        d = select((float16)(0.0f), lgn_sigmoid_backward16(vload16(0, d_rgb + c * s + i), r), valid);
      }
      vstore16(d, 0, deltas + (p.dy_row[last] + c) * s + i);
    }
  }
  for (uint l = last + 1; l-- > 0;) {
    mlp_layer_backward(W + p.w_offset[l], p.in[l], p.out[l], p.k_begin[l], p.mask[l],
                       deltas + p.dy_row[l] * s + i0, acts + p.x_row[l] * s + i0,
                       deltas + p.dx_row[l] * s + i0, s, i0, p.n16);
    if (l != p.geo_layer) continue;
    for (uint i = i0; i < i0 + 32 && i < p.n16; i += 16) {
      // The raw density's delta: the colour network's share plus dL/dsigma * dsigma/draw.
      const int16 valid = mlp_valid16(i, p.n);
      __global float* dr = deltas + p.dy_row[l - 1] * s + i;
      const float16 raw = vload16(0, acts + p.raw_row * s + i);
      const float16 grad = lgn_sigma_grad16(raw, lgn_sigma_from_raw16(raw));
      float16 ds = 0.0f;
      if (i + 16 <= p.n) {
        ds = vload16(0, d_sigma + i);
      } else {  // d_sigma holds only n values
        float tail[16];
        for (uint k = 0; k < 16; ++k) tail[k] = i + k < p.n ? d_sigma[i + k] : 0.0f;
        ds = vload16(0, tail);
      }
      vstore16(vload16(0, dr) + select((float16)(0.0f), ds * grad, valid), 0, dr);
    }
  }
}
