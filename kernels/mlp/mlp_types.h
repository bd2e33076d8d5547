// Parameters of the tiny-MLP kernels and the math they share with the host reference: spherical
// harmonics of the view direction, the activations and the density head (LGN_DEFINE_MLP_MATH).
// Activations are structure-of-arrays [row][stride]; weights are row-major [out][in] inside the
// flat parameter vector (no biases, as tiny-cuda-nn); every width is a multiple of 4 and kernels
// process 16 samples per work-item.
#pragma once
#include "common/cl_compat.h"

#define LGN_ACT_NONE 0u
#define LGN_ACT_RELU 1u
#define LGN_ACT_SIGMOID 2u
#define LGN_SIGMA_MAX_RAW 15.0f  // sigma = exp(min(raw, 15)): no overflow, gradient 0 beyond
// GPU weight-gradient partials (mlp_weight_grad_partial_tiled): samples per local-memory tile and
// weights per work-item (a layer of in * out weights needs in * out / 16 work-items per group).
#define LGN_MLP_GRAD_TILE 32u
#define LGN_MLP_GRAD_PER_ITEM 16u

typedef struct MlpParams {
  lgn_uint n;         // valid samples
  lgn_uint n16;       // samples processed (n rounded up to 16; padded samples carry zeros)
  lgn_uint stride;    // row stride of every activation buffer (max_batch)
  lgn_uint in;        // input rows = W row length (padded width)
  lgn_uint out;       // output rows computed (multiple of 4)
  lgn_uint w_offset;  // W[0][0] in the parameter vector
  lgn_uint x_row;     // first input row inside the x buffer
  lgn_uint y_row;     // first output / delta row inside the y buffer
  lgn_uint dx_row;    // first row of the input delta (backward)
  lgn_uint k_begin;   // backward: first input row whose delta is needed (multiple of 4)
  lgn_uint act;       // forward: activation of y; backward: LGN_ACT_RELU masks dx by x > 0
  lgn_uint chunk;     // weight-gradient partials: samples per chunk (multiple of 16)
  lgn_uint chunks;    // number of chunks
  lgn_uint aux;       // head kernels: SH coefficient count / geo rows; gradient fold: lanes
  lgn_uint pad0, pad1;
} MlpParams;

LGN_STATIC_ASSERT(sizeof(MlpParams) == 64, "MlpParams layout");

// A fused chain of dense layers (mlp_chain.cl): every activation lives in one buffer `acts` and
// every delta in one buffer `deltas`, each [row][stride], so a work-item runs all layers on its
// 32 samples while they are still in its cache. Layer l reads acts rows x_row[l].., writes acts
// rows y_row[l]..; backward reads deltas rows dy_row[l].., writes deltas rows dx_row[l] + k for
// k >= k_begin[l], masked by acts x > 0 when mask[l].
#define LGN_MLP_MAX_LAYERS 12
typedef struct MlpChainParams {
  lgn_uint n, n16, stride, layers;
  lgn_uint rgb_row;    // acts row of the sigmoid RGB output (3 rows + 1 padding row)
  lgn_uint raw_row;    // acts row of the raw density (geo feature 0)
  lgn_uint geo_layer;  // backward: after this layer's input delta, add dL/dsigma dsigma/draw at raw
  lgn_uint pad0;
  lgn_uint in[LGN_MLP_MAX_LAYERS], out[LGN_MLP_MAX_LAYERS], w_offset[LGN_MLP_MAX_LAYERS];
  lgn_uint act[LGN_MLP_MAX_LAYERS], x_row[LGN_MLP_MAX_LAYERS], y_row[LGN_MLP_MAX_LAYERS];
  lgn_uint dx_row[LGN_MLP_MAX_LAYERS], dy_row[LGN_MLP_MAX_LAYERS], k_begin[LGN_MLP_MAX_LAYERS];
  lgn_uint mask[LGN_MLP_MAX_LAYERS];
} MlpChainParams;

LGN_STATIC_ASSERT(sizeof(MlpChainParams) == 32 + 10 * 4 * LGN_MLP_MAX_LAYERS, "MlpChainParams layout");

// The activations and the density head with their derivatives, written once and stamped out per
// type (OpenCL C 1.2 has neither templates nor overloading): float (suffix none; the per-sample
// kernels), float16 (suffix 16; the CPU kernels, OpenCL only) and double (suffix _d; the host
// reference of tests/host/field, C++ only). On float16 the comparison selects per lane.
#define LGN_DEFINE_MLP_MATH(T, SFX)                                                              \
  /* y = act(a), act one of LGN_ACT_* */                                                         \
  LGN_INLINE T lgn_activate##SFX(T a, lgn_uint act) {                                            \
    if (act == LGN_ACT_RELU) return fmax(a, (T)(0.0f));                                          \
    if (act == LGN_ACT_SIGMOID) return (T)(1.0f) / ((T)(1.0f) + exp(-a));                        \
    return a;                                                                                    \
  }                                                                                              \
  /* dL/da of a sigmoid output y = sigmoid(a) given dL/dy */                                     \
  LGN_INLINE T lgn_sigmoid_backward##SFX(T dy, T y) { return dy * y * ((T)(1.0f) - y); }         \
  /* sigma = exp(min(raw, 15)) */                                                                \
  LGN_INLINE T lgn_sigma_from_raw##SFX(T raw) { return exp(fmin(raw, (T)(LGN_SIGMA_MAX_RAW))); } \
  /* d sigma / d raw given sigma and raw: the exact derivative of exp(min(raw, 15)) */           \
  LGN_INLINE T lgn_sigma_grad##SFX(T raw, T sigma) {                                             \
    return raw < (T)(LGN_SIGMA_MAX_RAW) ? sigma : (T)(0.0f);                                     \
  }

LGN_DEFINE_MLP_MATH(float, )
#ifdef __OPENCL_C_VERSION__
LGN_DEFINE_MLP_MATH(float16, 16)
#else
LGN_DEFINE_MLP_MATH(double, _d)
#endif

// Real spherical harmonics of a unit direction, degree 1..4 (degree^2 coefficients), the basis
// and constants of tiny-cuda-nn's SphericalHarmonics encoding. Stamped for float (sh_basis) and, in
// OpenCL, float16 (sh_basis16: 16 directions per call, the same value per lane as sh_basis).
#define LGN_DEFINE_SH_BASIS(T, SFX)                                                 \
  LGN_INLINE void sh_basis##SFX(T x, T y, T z, lgn_uint degree, T* out) {           \
    const T xy = x * y, xz = x * z, yz = y * z, x2 = x * x, y2 = y * y, z2 = z * z; \
    out[0] = 0.28209479177387814f;                                                  \
    if (degree <= 1u) return;                                                       \
    out[1] = -0.48860251190291987f * y;                                             \
    out[2] = 0.48860251190291987f * z;                                              \
    out[3] = -0.48860251190291987f * x;                                             \
    if (degree <= 2u) return;                                                       \
    out[4] = 1.0925484305920792f * xy;                                              \
    out[5] = -1.0925484305920792f * yz;                                             \
    out[6] = 0.94617469575755997f * z2 - 0.31539156525251999f;                      \
    out[7] = -1.0925484305920792f * xz;                                             \
    out[8] = 0.54627421529603959f * x2 - 0.54627421529603959f * y2;                 \
    if (degree <= 3u) return;                                                       \
    out[9] = 0.59004358992664352f * y * (-3.0f * x2 + y2);                          \
    out[10] = 2.8906114426405538f * xy * z;                                         \
    out[11] = 0.45704579946446572f * y * (1.0f - 5.0f * z2);                        \
    out[12] = 0.3731763325901154f * z * (5.0f * z2 - 3.0f);                         \
    out[13] = 0.45704579946446572f * x * (1.0f - 5.0f * z2);                        \
    out[14] = 1.4453057213202769f * z * (x2 - y2);                                  \
    out[15] = 0.59004358992664352f * x * (-x2 + 3.0f * y2);                         \
  }

LGN_DEFINE_SH_BASIS(float, )
#ifdef __OPENCL_C_VERSION__
LGN_DEFINE_SH_BASIS(float16, 16)
#endif
