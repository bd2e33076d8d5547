// Fused MLP chains, GPU variant: one work-item per sample runs every layer of the network (same
// MlpChainParams and the same results as mlp_chain.cl, which is shaped for CPUs with 16-sample
// float16 vectors and would spill registers on a GPU). Activations stay [row][stride], so the
// work-items of a group read and write consecutive addresses (coalesced), and every work-item
// reads the same weight at the same time (a broadcast from cache). Four outputs per pass over the
// inputs keep four independent FMA chains in flight.
#include "mlp/mlp_backward1.h"
#include "mlp/mlp_layer1.h"

// y[j] = act(sum_k W[j][k] x[k]) for j < out (out is a multiple of 4); x, y point at sample i's row 0.
LGN_DEFINE_MLP_LAYER_FORWARD1(mlp_layer_forward1, __global, __global, __global)

// dx[k] = (sum_j W[j][k] dy[j]) * (relu ? x[k] > 0 : 1) for k_begin <= k < in (both multiples of 4).
LGN_DEFINE_MLP_LAYER_BACKWARD1(mlp_layer_backward1, __global, __global, __global)

// Global size: n16 (padded samples carry zeros, as in the CPU variant).
__kernel void mlp_chain_forward(const MlpChainParams p, __global const float* restrict W,
                                __global float* acts) {
  const uint i = get_global_id(0);
  if (i >= p.n16) return;
  const uint s = p.stride;
  for (uint l = 0; l < p.layers; ++l)
    mlp_layer_forward1(W + p.w_offset[l], p.in[l], p.out[l], p.act[l], acts + p.x_row[l] * s + i, s,
                       acts + p.y_row[l] * s + i, s);
}

// Global size as mlp_chain_forward. d_sigma: n values; d_rgb: 3 rows of stride.
__kernel void mlp_chain_backward(const MlpChainParams p, __global const float* restrict W,
                                 __global const float* acts, __global float* deltas,
                                 __global const float* restrict d_sigma,
                                 __global const float* restrict d_rgb) {
  const uint i = get_global_id(0);
  if (i >= p.n16) return;
  const uint s = p.stride, last = p.layers - 1;
  const int valid = i < p.n;
  mlp_rgb_output_delta(&p, acts, deltas, d_rgb, i, valid);
  for (uint l = last + 1; l-- > 0;) {
    mlp_layer_backward1(W + p.w_offset[l], p.in[l], p.out[l], p.k_begin[l], p.mask[l],
                        deltas + p.dy_row[l] * s + i, s, acts + p.x_row[l] * s + i, s,
                        deltas + p.dx_row[l] * s + i, s);
    if (l == p.geo_layer && valid) mlp_add_sigma_delta(&p, acts, deltas, d_sigma, l, i);
  }
}
