// Adam over the flat parameter vector, one work-item per parameter (see adam/adam_types.h).
#include "adam/adam_types.h"

__kernel void adam_step(const AdamParams a, __global float* restrict params,
                        __global const float* restrict grads, __global float* restrict m,
                        __global float* restrict v) {
  const uint i = get_global_id(0);
  if (i >= a.count) return;
  float mi = m[i], vi = v[i];
  params[i] = adam_update(&a, i, params[i], grads[i], &mi, &vi);
  m[i] = mi;
  v[i] = vi;
}
