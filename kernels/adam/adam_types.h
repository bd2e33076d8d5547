// Parameters of the Adam kernel: bias-corrected Adam over the flat parameter vector, with L2 weight
// decay (added to the gradient) on the MLP part [mlp_offset, count) only, as instant-ngp does.
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
} AdamParams;

LGN_STATIC_ASSERT(sizeof(AdamParams) == 40, "AdamParams layout");

// One Adam update of a single parameter; returns the new value and updates the moments.
LGN_INLINE float adam_update(const AdamParams* a, lgn_uint i, float p, float g, float* m, float* v) {
  if (i >= a->mlp_offset) g += a->weight_decay * p;
  *m = a->beta1 * *m + (1.0f - a->beta1) * g;
  *v = a->beta2 * *v + (1.0f - a->beta2) * g * g;
  const float mhat = *m / a->bias1;
  const float vhat = *v / a->bias2;
  return p - a->lr * mhat / (sqrt(vhat) + a->eps);
}
