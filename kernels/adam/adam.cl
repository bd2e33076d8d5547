// Adam over the flat parameter vector, one work-item per parameter (see adam/adam_types.h); it
// clears the gradients below clear_below after reading them and leaves parameters below
// skip_zero_below alone when their gradient is zero (sparse hash-table updates: most entries of the
// fine levels get no gradient in a step, and skipping them saves 24 of their 28 bytes of traffic).
#include "adam/adam_types.h"

__kernel void adam_step(const AdamParams a, __global float* restrict params, __global float* restrict grads,
                        __global float* restrict m, __global float* restrict v) {
  const uint i = get_global_id(0);
  if (i >= a.count) return;
  const float g = grads[i];
  if (g == 0.0f && i < a.skip_zero_below) return;  // nothing to clear either
  if (i < a.clear_below) grads[i] = 0.0f;
  float mi = m[i], vi = v[i];
  params[i] = adam_update(&a, i, params[i], g, &mi, &vi);
  m[i] = mi;
  v[i] = vi;
}
