// Analytic density/colour fields (boxes and spheres of constant density, march_math.h) evaluated
// in place of the NeRF field, with the field's interface: SoA positions normalised to the AABB in,
// sigma and rgb (SoA, same stride) out. Tests and benchmarks use it for closed-form scenes.
#include "march/march_math.h"

__kernel void analytic_field_eval(const AnalyticFieldParams p, __global const float* pos,
                                  __global float* sigma, __global float* rgb) {
  const uint j = get_global_id(0);
  if (j >= p.count) return;
  const uint S = p.stride;
  const float pos_j[3] = {pos[j], pos[S + j], pos[2 * S + j]};
  float s, c[3];
  analytic_eval_normalised(&p, pos_j, &s, c);
  sigma[j] = s;
  rgb[j] = c[0];
  rgb[S + j] = c[1];
  rgb[2 * S + j] = c[2];
}
