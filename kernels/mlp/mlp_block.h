// OpenCL-only: the dense-layer bodies shared by the single-layer kernels (mlp.cl) and the fused
// chains (mlp_chain.cl). A call handles the 32 samples from i0 (16 when i0 + 16 >= n16) in two
// float16 halves: 8 rows x 2 halves = 16 independent FMA chains per 2 sample loads + 8 weight
// broadcasts, so the FMA units rather than the load ports set the pace; remainders in 4-row blocks.
// Pointers point at row 0 of the layer's input / output at sample i0; s is the row stride.
#pragma once
#include "mlp/mlp_types.h"

inline float mlp_hsum(float16 a) {
  float8 h = a.lo + a.hi;
  float4 q = h.lo + h.hi;
  float2 r = q.lo + q.hi;
  return r.x + r.y;
}

#define MLP_ZERO4 float16 a0 = 0.0f, a1 = 0.0f, a2 = 0.0f, a3 = 0.0f

#define MLP_FMA8(a, xv, w, in, k)                       \
  a##0 = fma((float16)((w)[k]), xv, a##0);              \
  a##1 = fma((float16)((w)[(in) + (k)]), xv, a##1);     \
  a##2 = fma((float16)((w)[2 * (in) + (k)]), xv, a##2); \
  a##3 = fma((float16)((w)[3 * (in) + (k)]), xv, a##3); \
  a##4 = fma((float16)((w)[4 * (in) + (k)]), xv, a##4); \
  a##5 = fma((float16)((w)[5 * (in) + (k)]), xv, a##5); \
  a##6 = fma((float16)((w)[6 * (in) + (k)]), xv, a##6); \
  a##7 = fma((float16)((w)[7 * (in) + (k)]), xv, a##7)
#define MLP_STORE8(a, o, s, act)                         \
  vstore16(lgn_activate16(a##0, act), 0, (o));           \
  vstore16(lgn_activate16(a##1, act), 0, (o) + (s));     \
  vstore16(lgn_activate16(a##2, act), 0, (o) + 2 * (s)); \
  vstore16(lgn_activate16(a##3, act), 0, (o) + 3 * (s)); \
  vstore16(lgn_activate16(a##4, act), 0, (o) + 4 * (s)); \
  vstore16(lgn_activate16(a##5, act), 0, (o) + 5 * (s)); \
  vstore16(lgn_activate16(a##6, act), 0, (o) + 6 * (s)); \
  vstore16(lgn_activate16(a##7, act), 0, (o) + 7 * (s))

inline float16 mlp_mask(float16 d, __global const float* x, uint relu) {
  return relu ? select((float16)(0.0f), d, vload16(0, x) > 0.0f) : d;
}

#define MLP_FMA8T(a, d, wj)                \
  a##0 = fma((float16)((wj)[0]), d, a##0); \
  a##1 = fma((float16)((wj)[1]), d, a##1); \
  a##2 = fma((float16)((wj)[2]), d, a##2); \
  a##3 = fma((float16)((wj)[3]), d, a##3); \
  a##4 = fma((float16)((wj)[4]), d, a##4); \
  a##5 = fma((float16)((wj)[5]), d, a##5); \
  a##6 = fma((float16)((wj)[6]), d, a##6); \
  a##7 = fma((float16)((wj)[7]), d, a##7)
#define MLP_STORE8M(a, o, xb, s, relu)                              \
  vstore16(mlp_mask(a##0, (xb), relu), 0, (o));                     \
  vstore16(mlp_mask(a##1, (xb) + (s), relu), 0, (o) + (s));         \
  vstore16(mlp_mask(a##2, (xb) + 2 * (s), relu), 0, (o) + 2 * (s)); \
  vstore16(mlp_mask(a##3, (xb) + 3 * (s), relu), 0, (o) + 3 * (s)); \
  vstore16(mlp_mask(a##4, (xb) + 4 * (s), relu), 0, (o) + 4 * (s)); \
  vstore16(mlp_mask(a##5, (xb) + 5 * (s), relu), 0, (o) + 5 * (s)); \
  vstore16(mlp_mask(a##6, (xb) + 6 * (s), relu), 0, (o) + 6 * (s)); \
  vstore16(mlp_mask(a##7, (xb) + 7 * (s), relu), 0, (o) + 7 * (s))

#include "mlp/mlp_forward16.h"

// y[j] = act(sum_k W[j][k] x[k]) for j < out; W points at the layer's first weight.
LGN_DEFINE_MLP_LAYER_FORWARD16(mlp_layer_forward, __global, __global)

// dx[k] = (sum_j W[j][k] dz[j]) * (relu ? x[k] > 0 : 1) for k_begin <= k < in.
inline void mlp_layer_backward(__global const float* restrict W, uint in, uint out, uint k_begin, uint relu,
                               __global const float* restrict db, __global const float* restrict xb,
                               __global float* restrict ob, uint s, uint i0, uint n16) {
  uint k = k_begin;
  if (i0 + 16 < n16) {
    for (; k + 8 <= in; k += 8) {
      __global const float* w = W + k;
      float16 a0 = 0.0f, a1 = 0.0f, a2 = 0.0f, a3 = 0.0f, a4 = 0.0f, a5 = 0.0f, a6 = 0.0f, a7 = 0.0f;
      float16 b0 = 0.0f, b1 = 0.0f, b2 = 0.0f, b3 = 0.0f, b4 = 0.0f, b5 = 0.0f, b6 = 0.0f, b7 = 0.0f;
      for (uint j = 0; j < out; ++j) {
        const float16 da = vload16(0, db + j * s), dc = vload16(0, db + j * s + 16);
        __global const float* wj = w + j * in;
        MLP_FMA8T(a, da, wj);
        MLP_FMA8T(b, dc, wj);
      }
      MLP_STORE8M(a, ob + k * s, xb + k * s, s, relu);
      MLP_STORE8M(b, ob + k * s + 16, xb + k * s + 16, s, relu);
    }
  }
  for (uint h16 = 0; h16 < 32 && i0 + h16 < n16; h16 += 16) {
    for (uint kk = k; kk < in; kk += 4) {
      __global const float* w = W + kk;
      MLP_ZERO4;
      for (uint j = 0; j < out; ++j) {
        const float16 d = vload16(0, db + j * s + h16);
        __global const float* wj = w + j * in;
        a0 = fma((float16)(wj[0]), d, a0);
        a1 = fma((float16)(wj[1]), d, a1);
        a2 = fma((float16)(wj[2]), d, a2);
        a3 = fma((float16)(wj[3]), d, a3);
      }
      __global float* o = ob + kk * s + h16;
      __global const float* xk = xb + kk * s + h16;
      vstore16(mlp_mask(a0, xk, relu), 0, o);
      vstore16(mlp_mask(a1, xk + s, relu), 0, o + s);
      vstore16(mlp_mask(a2, xk + 2 * s, relu), 0, o + 2 * s);
      vstore16(mlp_mask(a3, xk + 3 * s, relu), 0, o + 3 * s);
    }
  }
}
