// Tiny-MLP kernels on structure-of-arrays activations, 32 samples per work-item in explicit
// float16 vectors (PoCL vectorises these, not loops across work-items): single dense layers
// y = act(W x) and their input deltas (W^T dz, masked by the ReLU of the input) — the Field runs
// the fused chains of mlp_chain.cl instead —, weight gradients as per-chunk partial sums over the
// samples followed by a fixed-order reduction over the chunks (deterministic, no atomics), and the
// SH-encoding and sigma heads.
#include "mlp/mlp_block.h"

// y[y_row + j] = act(sum_k W[j][k] x[x_row + k]) for j < out. Global size: n16 / 16 rounded up
// to n32 / 32 (32 samples per work-item).
__kernel void mlp_forward(const MlpParams p, __global const float* restrict W,
                          __global const float* restrict x, __global float* restrict y) {
  const uint i0 = get_global_id(0) * 32;
  if (i0 >= p.n16) return;
  const uint s = p.stride;
  mlp_layer_forward(W + p.w_offset, p.in, p.out, p.act, x + p.x_row * s + i0, y + p.y_row * s + i0, s, i0,
                    p.n16);
}

// dx[dx_row + k] = (sum_j W[j][k] dz[y_row + j]) * (act == RELU ? x[x_row + k] > 0 : 1), for
// k_begin <= k < in. Global size as mlp_forward.
__kernel void mlp_backward_input(const MlpParams p, __global const float* restrict W,
                                 __global const float* restrict dz, __global const float* restrict x,
                                 __global float* restrict dx) {
  const uint i0 = get_global_id(0) * 32;
  if (i0 >= p.n16) return;
  const uint s = p.stride;
  mlp_layer_backward(W + p.w_offset, p.in, p.out, p.k_begin, p.act == LGN_ACT_RELU, dz + p.y_row * s + i0,
                     x + p.x_row * s + i0, dx + p.dx_row * s + i0, s, i0, p.n16);
}

#define MLP_OUTER(a, d, x0, x1, x2, x3) \
  a##0 = fma(d, x0, a##0);              \
  a##1 = fma(d, x1, a##1);              \
  a##2 = fma(d, x2, a##2);              \
  a##3 = fma(d, x3, a##3)
#define MLP_STORE4(o, a)   \
  (o)[0] = mlp_hsum(a##0); \
  (o)[1] = mlp_hsum(a##1); \
  (o)[2] = mlp_hsum(a##2); \
  (o)[3] = mlp_hsum(a##3)

// partial[c][j][k] = sum over the samples of chunk c of dz[y_row + j] * x[x_row + k], for a 4x4
// block (j, k) per work-item (16 independent accumulators, 8 loads per 16 FMAs).
// Global size: (out/4 * in/4, chunks): blocks vary fastest, so consecutive work-groups work on
// the same chunk while its rows are in cache.
__kernel void mlp_weight_grad_partial(const MlpParams p, __global const float* restrict dz,
                                      __global const float* restrict x, __global float* restrict partial) {
  const uint blk = get_global_id(0);
  const uint c = get_global_id(1);
  const uint kblocks = p.in / 4;
  if (c >= p.chunks || blk >= (p.out / 4) * kblocks) return;
  const uint j = (blk / kblocks) * 4, k = (blk % kblocks) * 4;
  const uint s = p.stride;
  const uint begin = c * p.chunk;
  const uint end = min(begin + p.chunk, p.n16);
  __global const float* db = dz + (p.y_row + j) * s;
  __global const float* xb = x + (p.x_row + k) * s;
  float16 a0 = 0.0f, a1 = 0.0f, a2 = 0.0f, a3 = 0.0f, b0 = 0.0f, b1 = 0.0f, b2 = 0.0f, b3 = 0.0f;
  float16 c0 = 0.0f, c1 = 0.0f, c2 = 0.0f, c3 = 0.0f, e0 = 0.0f, e1 = 0.0f, e2 = 0.0f, e3 = 0.0f;
  for (uint i = begin; i < end; i += 16) {
    const float16 x0 = vload16(0, xb + i), x1 = vload16(0, xb + s + i);
    const float16 x2 = vload16(0, xb + 2 * s + i), x3 = vload16(0, xb + 3 * s + i);
    const float16 d0 = vload16(0, db + i), d1 = vload16(0, db + s + i);
    const float16 d2 = vload16(0, db + 2 * s + i), d3 = vload16(0, db + 3 * s + i);
    MLP_OUTER(a, d0, x0, x1, x2, x3);
    MLP_OUTER(b, d1, x0, x1, x2, x3);
    MLP_OUTER(c, d2, x0, x1, x2, x3);
    MLP_OUTER(e, d3, x0, x1, x2, x3);
  }
  __global float* out = partial + (c * p.out + j) * p.in + k;
  MLP_STORE4(out, a);
  MLP_STORE4(out + p.in, b);
  MLP_STORE4(out + 2 * p.in, c);
  MLP_STORE4(out + 3 * p.in, e);
}

// GPU variant of the partials (the kernel above keeps 256 floats per work-item in float16
// registers, which a GPU would spill): one work-group per chunk, each work-item owns the weights
// e = lid + q * group size (q < LGN_MLP_GRAD_PER_ITEM) of the layer and sums dz[j] x[k] over the
// chunk's samples in order, so the result is deterministic. The chunk's input and delta rows pass
// through local memory in tiles of LGN_MLP_GRAD_TILE samples (loaded coalesced; rows padded by one
// float so neighbouring weights read different banks). Global size: chunks * group size; local
// scratch (in + out) * (LGN_MLP_GRAD_TILE + 1) floats.
__kernel void mlp_weight_grad_partial_tiled(const MlpParams p, __global const float* restrict dz,
                                            __global const float* restrict x,
                                            __global float* restrict partial, __local float* tile) {
  const uint c = get_group_id(0), lid = get_local_id(0), G = get_local_size(0);
  const uint count = p.out * p.in, s = p.stride, ts = LGN_MLP_GRAD_TILE + 1;
  const uint begin = c * p.chunk, end = min(begin + p.chunk, p.n16);
  __local const float* xt = tile;              // [in][ts]
  __local const float* dt = tile + p.in * ts;  // [out][ts]
  float acc[LGN_MLP_GRAD_PER_ITEM];
  for (uint q = 0; q < LGN_MLP_GRAD_PER_ITEM; ++q) acc[q] = 0.0f;
  for (uint t0 = begin; t0 < end; t0 += LGN_MLP_GRAD_TILE) {
    barrier(CLK_LOCAL_MEM_FENCE);  // the previous tile is used up
    for (uint e = lid; e < (p.in + p.out) * LGN_MLP_GRAD_TILE; e += G) {
      const uint row = e / LGN_MLP_GRAD_TILE, t = e % LGN_MLP_GRAD_TILE, i = t0 + t;
      float v = 0.0f;
      if (i < end) v = row < p.in ? x[(p.x_row + row) * s + i] : dz[(p.y_row + row - p.in) * s + i];
      tile[row * ts + t] = v;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint q = 0; q < LGN_MLP_GRAD_PER_ITEM; ++q) {
      const uint e = lid + q * G;
      if (e >= count) break;
      __local const float* d = dt + (e / p.in) * ts;
      __local const float* xk = xt + (e % p.in) * ts;
      float a = acc[q];
      for (uint t = 0; t < LGN_MLP_GRAD_TILE; ++t) a = fma(d[t], xk[t], a);
      acc[q] = a;
    }
  }
  for (uint q = 0; q < LGN_MLP_GRAD_PER_ITEM; ++q) {
    const uint e = lid + q * G;
    if (e < count) partial[c * count + e] = acc[q];
  }
}

// Many chunks (the GPU split): partial[r][e] = sum of partial[c][e] over c = r, r + aux, r + 2 aux,
// ... < chunks, in that order, for lane r < aux. In place: chunk r belongs to lane r alone and is its
// first term. Global size: (out * in rounded up, aux); mlp_weight_grad_reduce then sums the lanes.
__kernel void mlp_weight_grad_fold(const MlpParams p, __global float* restrict partial) {
  const uint e = get_global_id(0), r = get_global_id(1);
  const uint count = p.out * p.in;
  if (e >= count || r >= p.aux) return;
  float sum = 0.0f;
  for (uint c = r; c < p.chunks; c += p.aux) sum += partial[c * count + e];
  partial[r * count + e] = sum;
}

// grads[w_offset + e] = sum_c partial[c][e] in chunk order. Global size: out * in.
__kernel void mlp_weight_grad_reduce(const MlpParams p, __global const float* restrict partial,
                                     __global float* restrict grads) {
  const uint e = get_global_id(0);
  const uint count = p.out * p.in;
  if (e >= count) return;
  float sum = 0.0f;
  for (uint c = 0; c < p.chunks; ++c) sum += partial[c * count + e];
  grads[p.w_offset + e] = sum;
}

// color_in[y_row + 0 .. aux) = SH basis of the direction (degree sqrt(aux)); zeros for padded samples.
// Global size: n16.
__kernel void mlp_sh_encode(const MlpParams p, __global const float* restrict dir,
                            __global float* restrict color_in) {
  const uint i = get_global_id(0);
  if (i >= p.n16) return;
  const uint s = p.stride;
  float sh[16];
  for (int c = 0; c < 16; ++c) sh[c] = 0.0f;
  if (i < p.n) {
    const uint degree = p.aux == 16u ? 4u : p.aux == 9u ? 3u : p.aux == 4u ? 2u : 1u;
    sh_basis(dir[i], dir[s + i], dir[2 * s + i], degree, sh);
  }
  for (uint c = 0; c < p.aux; ++c) color_in[(p.y_row + c) * s + i] = sh[c];
}

// sigma[i] = exp(min(raw, 15)) with raw = geo[y_row][i]. Global size: n.
__kernel void mlp_sigma(const MlpParams p, __global const float* restrict geo,
                        __global float* restrict sigma) {
  const uint i = get_global_id(0);
  if (i >= p.n) return;
  sigma[i] = lgn_sigma_from_raw(geo[p.y_row * p.stride + i]);
}
