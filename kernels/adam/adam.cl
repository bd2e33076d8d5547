// Adam over the flat parameter vector, one work-item per parameter (see adam/adam_types.h); it
// clears the gradients below clear_below after reading them.
#include "adam/adam_types.h"

__kernel void adam_step(const AdamParams a, __global float* restrict params, __global float* restrict grads,
                        __global float* restrict m, __global float* restrict v) {
  const uint i = get_global_id(0);
  if (i >= a.count) return;
  float mi = m[i], vi = v[i];
  const float g = grads[i];
  if (i < a.clear_below) grads[i] = 0.0f;
  params[i] = adam_update(&a, i, params[i], g, &mi, &vi);
  m[i] = mi;
  v[i] = vi;
}
