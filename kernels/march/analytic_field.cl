// Analytic density/colour fields (boxes and spheres of constant density, march_math.h) evaluated
// in place of the NeRF field, with the field's interface: SoA positions normalised to the AABB in,
// sigma and rgb (SoA, same stride) out. Tests and benchmarks use it for closed-form scenes.
#include "march/march_math.h"

__kernel void analytic_field_eval(const AnalyticFieldParams p, __global const float* pos,
                                  __global float* sigma, __global float* rgb) {
  const uint j = get_global_id(0);
  if (j >= p.count) return;
  const uint S = p.stride;
  float x = p.aabb_min[0] + pos[j] * (p.aabb_max[0] - p.aabb_min[0]);
  float y = p.aabb_min[1] + pos[S + j] * (p.aabb_max[1] - p.aabb_min[1]);
  float z = p.aabb_min[2] + pos[2 * S + j] * (p.aabb_max[2] - p.aabb_min[2]);
  float s, c[3];
  analytic_eval(&p, x, y, z, &s, c);
  sigma[j] = s;
  rgb[j] = c[0];
  rgb[S + j] = c[1];
  rgb[2 * S + j] = c[2];
}
