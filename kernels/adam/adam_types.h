// Parameters of the Adam kernel: bias-corrected Adam over the flat parameter vector, with L2 weight
// decay (added to the gradient) on the MLP part [mlp_offset, count) only, as instant-ngp does.
// Sparse hash updates (skip_zero_below > 0): a parameter below skip_zero_below whose gradient is
// exactly zero this step is not touched at all (value and both moments kept), as tiny-cuda-nn does
// for its non-matrix (hash-table) parameters; every other parameter gets the dense update. One
// difference from tiny-cuda-nn: the bias correction uses the global step t for every parameter
// (tiny-cuda-nn counts steps per parameter), so an entry first touched late is corrected with
// 1 - beta^t ~ 1, which equals its per-parameter correction only once t is large.
#pragma once
#include "common/cl_compat.h"

typedef struct AdamParams {
  lgn_uint count;       // parameters
  lgn_uint mlp_offset;  // first MLP parameter (weight decay applies from here on)
  float lr, beta1, beta2, eps, weight_decay;
  float bias1;  // 1 - beta1^t
  float bias2;  // 1 - beta2^t
  // Gradients [0, clear_below) are set to zero once used: the hash-grid backward accumulates into
  // zeros, and clearing them here saves a separate pass over the table (0: nothing cleared).
  lgn_uint clear_below;
  lgn_uint skip_zero_below;  // parameters [0, skip_zero_below) with a zero gradient are left as they are
  lgn_uint pad;
} AdamParams;

LGN_STATIC_ASSERT(sizeof(AdamParams) == 48, "AdamParams layout");

// One Adam update of a single parameter; returns the new value and updates the moments.
LGN_INLINE float adam_update(const AdamParams* a, lgn_uint i, float p, float g, float* m, float* v) {
  if (i >= a->mlp_offset) g += a->weight_decay * p;
  *m = a->beta1 * *m + (1.0f - a->beta1) * g;
  *v = a->beta2 * *v + (1.0f - a->beta2) * g * g;
  const float mhat = *m / a->bias1;
  const float vhat = *v / a->bias2;
  return p - a->lr * mhat / (sqrt(vhat) + a->eps);
}
