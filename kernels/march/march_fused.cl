// The fused compositing marcher, shaped for GPUs: one work-item marches one ray from the box entry
// to its end in a single kernel launch per tile: occupancy skipping (march_math.h), the field per
// sample (march_fused_field.h: hash encoding + MLP with the weights in local memory, or an analytic
// field), the surface of paper Eq. 7 inserted at its exact depth (the step holding S_t is split
// there; premultiplied S_c and coverage S_α added, what lies behind seen through T(1 - S_α) and the
// filter F; an opaque surface ends the march at S_t) and early termination once T < min. No host
// round trip per wave and no compaction: a ray's samples never leave its work-item.
//
// The sample sequence is the wavefront marcher's (march.cl: march_step, march_composite), step for
// step: the same segment ends, midpoints, skips and sample budget, so the two agree up to the
// field's float rounding. Only the work differs: this kernel evaluates exactly the samples it
// composites (the wavefront one may evaluate a few past a ray's termination within a wave).
#include "march/march_fused_field.h"

// The surface of the pixel, composited once the march reaches S_t; its filter applies from then on.
inline void fused_pass_surface(MarchAccum* acc, uint* surface, float ts, __global const float* ca,
                               __global const float* fl, float* filter) {
  march_add_surface(acc, ts, ca[0], ca[1], ca[2], ca[3]);
  *surface = LGN_SURF_PASSED;
  filter[0] = fl[0];
  filter[1] = fl[1];
  filter[2] = fl[2];
}

// Global size: ray_count rounded up to the work-group size; local_weights: mlp_count floats (NeRF
// with LGN_FUSED_LOCAL_WEIGHTS), else unused.
__kernel void march_fused(const MarchParams p, __constant const MarchFusedField* field,
                          __global const float* params, __global const uint* occ,
                          __global const float* surf_ca, __global const float* surf_depth,
                          __global const float* surf_filter, __global float* out_rgba,
                          __global float* out_depth, __global uint* out_samples,
                          __local float* local_weights) {
#if LGN_FUSED_FIELD == LGN_FUSED_NERF && LGN_FUSED_LOCAL_WEIGHTS
  for (uint k = get_local_id(0); k < field->mlp_count; k += get_local_size(0))
    local_weights[k] = params[field->mlp_begin + k];
  barrier(CLK_LOCAL_MEM_FENCE);
#endif
  const uint i = get_global_id(0);
  if (i >= p.ray_count) return;
  AnalyticFieldParams analytic;  // the analytic program's primitives, copied to private memory
#if LGN_FUSED_FIELD == LGN_FUSED_ANALYTIC
  analytic = field->analytic;
#endif
  const MarchRay r = march_ray_start(&p, i, surf_ca, surf_depth);
  const float t_end = r.t_end, ts = r.t_surface;
  const float o[3] = {r.ox, r.oy, r.oz}, d[3] = {r.dx, r.dy, r.dz};
  __global const float* ca = surf_ca + 4 * r.pixel;
  __global const float* fl = surf_filter + 3 * r.pixel;
  MarchAccum acc = {1.0f, 0.0f, 0.0f, 0.0f, 0.0f};
  float filter[3] = {1.0f, 1.0f, 1.0f};
  uint surface = r.surface, samples = 0;
  int done = 0;
  float t = r.t;
  while (!done && t < t_end) {
    if (samples >= p.max_samples) break;  // the safety bound: the ray ends here
    const float tm = fmin(t + 0.5f * p.step, 0.5f * (t + t_end));
    if (!march_occupied(p.occ_layout, p.occ_res, occ, p.aabb_min, p.aabb_max, o[0] + tm * d[0],
                        o[1] + tm * d[1], o[2] + tm * d[2])) {
      t += march_skip(p.aabb_min, p.aabb_max, p.occ_res, p.step, tm, o[0], o[1], o[2], d[0], d[1], d[2]);
      continue;
    }
    const float t1 = fmin(t + p.step, t_end);
    // One step, split at S_t when the pending surface lies inside it: [t, ts] then [ts, t1].
    const int split = surface == LGN_SURF_PENDING && ts > t && ts < t1;
    for (int part = 0; part <= split && !done; ++part) {
      const float a = part == 0 ? t : ts, b = (split && part == 0) ? ts : t1;
      if (surface == LGN_SURF_PENDING && a >= ts) {
        fused_pass_surface(&acc, &surface, ts, ca, fl, filter);
        if (acc.T < p.min_transmittance) {
          done = 1;
          break;
        }
      }
      float pos[3], sigma, rgb[3];
      march_sample_position(p.aabb_min, p.aabb_max, o[0], o[1], o[2], d[0], d[1], d[2], 0.5f * (a + b), pos);
      fused_field_eval(field, &analytic, params, local_weights, pos, d, &sigma, rgb);
      march_add_segment(&acc, a, b, sigma, filter[0] * rgb[0], filter[1] * rgb[1], filter[2] * rgb[2]);
      ++samples;
      if (acc.T < p.min_transmittance) done = 1;
    }
    t = t1;
  }
  // The march is over: a surface behind it still shows.
  if (!done && surface == LGN_SURF_PENDING) fused_pass_surface(&acc, &surface, ts, ca, fl, filter);
  march_write_pixel(&p, &acc, filter, r.pixel, samples, out_rgba, out_depth, out_samples);
}
