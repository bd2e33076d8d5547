// Fused MLP chains, GPU variant with the weights in local memory (tiny-cuda-nn's fully fused MLP):
// one work-item per sample runs every layer of the network, and before each layer its work-group
// copies that layer's weights into local memory, so the weights are read from global memory once
// per group instead of once per sample, and every multiply-add reads its weight from local memory
// (a broadcast: all work-items of a group read the same weight at the same time). Activations stay
// [row][stride] in global memory (coalesced across the group). Same MlpChainParams, the same
// per-sample summation order and so the same results bit for bit as mlp_chain_per_sample.cl,
// which the host uses instead when the largest layer does not fit the device's local memory.
// The caller passes local scratch of the largest layer's in * out floats.
#include "mlp/mlp_backward1.h"
#include "mlp/mlp_layer1.h"

LGN_DEFINE_MLP_LAYER_FORWARD1(mlp_layer_forward_local, __local, __global, __global)
LGN_DEFINE_MLP_LAYER_BACKWARD1(mlp_layer_backward_local, __local, __global, __global)

// w = the layer's count weights; every work-item of the group must call it.
inline void mlp_load_weights(__global const float* restrict W, uint count, __local float* w) {
  barrier(CLK_LOCAL_MEM_FENCE);  // the group is done with the previous layer's weights
  for (uint e = get_local_id(0); e < count; e += get_local_size(0)) w[e] = W[e];
  barrier(CLK_LOCAL_MEM_FENCE);
}

// Global size: n16 rounded up to the group size (samples n16.. of the last group only help load).
__kernel void mlp_chain_forward_local(const MlpChainParams p, __global const float* restrict W,
                                      __global float* acts, __local float* w) {
  const uint i = get_global_id(0);
  const int active = i < p.n16;
  const uint s = p.stride;
  for (uint l = 0; l < p.layers; ++l) {
    mlp_load_weights(W + p.w_offset[l], p.in[l] * p.out[l], w);
    if (active)
      mlp_layer_forward_local(w, p.in[l], p.out[l], p.act[l], acts + p.x_row[l] * s + i, s,
                              acts + p.y_row[l] * s + i, s);
  }
}

// Global size as mlp_chain_forward_local. d_sigma: n values; d_rgb: 3 rows of stride.
__kernel void mlp_chain_backward_local(const MlpChainParams p, __global const float* restrict W,
                                       __global const float* acts, __global float* deltas,
                                       __global const float* restrict d_sigma,
                                       __global const float* restrict d_rgb, __local float* w) {
  const uint i = get_global_id(0);
  const int active = i < p.n16, valid = i < p.n;
  const uint s = p.stride, last = p.layers - 1;
  if (active) mlp_rgb_output_delta(&p, acts, deltas, d_rgb, i, valid);
  for (uint l = last + 1; l-- > 0;) {
    mlp_load_weights(W + p.w_offset[l], p.in[l] * p.out[l], w);
    if (!active) continue;
    mlp_layer_backward_local(w, p.in[l], p.out[l], p.k_begin[l], p.mask[l], deltas + p.dy_row[l] * s + i, s,
                             acts + p.x_row[l] * s + i, s, deltas + p.dx_row[l] * s + i, s);
    if (l == p.geo_layer && valid) mlp_add_sigma_delta(&p, acts, deltas, d_sigma, l, i);
  }
}
