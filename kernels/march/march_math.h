// The marcher's math, written once for the kernels and the host reference (tests): ray/box
// clipping, the occupancy lookup and empty-cell skipping, the compositing rule (paper Eq. 7 with a
// premultiplied surface colour) and the analytic density/colour fields.
//
// Compositing (S_c premultiplied by coverage S_α, ARCHITECTURE.md): walking front to back with
// transmittance T, a NeRF segment of length Δ, density σ and colour c adds T·(1 − e^{−σΔ})·c and
// multiplies T by e^{−σΔ}; the surface at t_s adds T(t_s)·S_c and multiplies T by (1 − S_α). So
//   X = C(t_n, t_s) + T(t_s)·S_c + T(t_s)·(1 − S_α)·C_s(t_s, t_f)
// where C_s integrates with transmittance restarted at t_s. A tinted lens filters C_s (and the
// background) per channel by F (surface_buffers.h): the caller multiplies colours behind t_s by F.
// S_α = 1 ends the ray at t_s (the march
// never goes past it); S_α = 0 (no hit) leaves the ray bit-for-bit the NeRF-only one.
#pragma once
#include "common/composite.h"
#include "march/march_types.h"
#include "train/occupancy.h"

#ifndef __OPENCL_C_VERSION__
using std::ceil;
#endif
#define LGN_MARCH_INF INFINITY

// Intersects the ray with the box; returns 1 and the parametric range (clamped at t >= 0) on a hit.
LGN_INLINE int march_clip_aabb(const float* bmin, const float* bmax, float ox, float oy, float oz, float dx,
                               float dy, float dz, float* t0, float* t1) {
  float o[3] = {ox, oy, oz};
  float d[3] = {dx, dy, dz};
  float tn = 0.0f, tf = LGN_MARCH_INF;
  for (int a = 0; a < 3; ++a) {
    float inv = 1.0f / d[a];  // +-inf for axis-parallel rays: the slab test still works
    float ta = (bmin[a] - o[a]) * inv;
    float tb = (bmax[a] - o[a]) * inv;
    if (d[a] == 0.0f) {  // parallel to this slab: inside or not, independent of t
      if (o[a] < bmin[a] || o[a] > bmax[a]) return 0;
      continue;
    }
    tn = fmax(tn, fmin(ta, tb));
    tf = fmin(tf, fmax(ta, tb));
  }
  *t0 = tn;
  *t1 = tf;
  return tn < tf;
}

// Occupancy of the cell containing scene point p, by the trainer's rule (train/occupancy.h: res^3
// cells over the AABB in normalised coordinates; cells outside the grid are empty).
LGN_INLINE int march_occupied(lgn_uint layout, lgn_uint res, LGN_GLOBAL const lgn_uint* bits,
                              const float* bmin, const float* bmax, float px, float py, float pz) {
  if (layout == LGN_MARCH_OCC_NONE) return 1;
  return occ_test(bits, res, (px - bmin[0]) / (bmax[0] - bmin[0]), (py - bmin[1]) / (bmax[1] - bmin[1]),
                  (pz - bmin[2]) / (bmax[2] - bmin[2]));
}

// How far (in ray parameter) to jump from a sample at t in an empty cell: to the first position on
// the step grid past the cell's exit, as the training sampler does (kernels/train/sampling.cl), so
// inference takes the samples training took.
LGN_INLINE float march_skip(const float* bmin, const float* bmax, lgn_uint res, float step, float t, float ox,
                            float oy, float oz, float dx, float dy, float dz) {
  float ex = bmax[0] - bmin[0], ey = bmax[1] - bmin[1], ez = bmax[2] - bmin[2];
  float s = occ_cell_exit(res, (ox + t * dx - bmin[0]) / ex, (oy + t * dy - bmin[1]) / ey,
                          (oz + t * dz - bmin[2]) / ez, dx / ex, dy / ey, dz / ez);
  return step * fmax(ceil(s / step), 1.0f);
}

// Front-to-back accumulation state of one ray.
typedef struct MarchAccum {
  float T;
  float r, g, b;
  float depth_sum;
} MarchAccum;

// Adds one NeRF segment [t0, t1] of density sigma and colour (cr, cg, cb) by the compositing step
// the training loss uses (common/composite.h).
LGN_INLINE void march_add_segment(MarchAccum* acc, float t0, float t1, float sigma, float cr, float cg,
                                  float cb) {
  float w = lgn_composite_segment(&acc->T, sigma, t1 - t0);
  acc->r += w * cr;
  acc->g += w * cg;
  acc->b += w * cb;
  acc->depth_sum += w * 0.5f * (t0 + t1);
}

// Adds the surface at depth ts: premultiplied colour (sr, sg, sb) and coverage sa.
LGN_INLINE void march_add_surface(MarchAccum* acc, float ts, float sr, float sg, float sb, float sa) {
  acc->r += acc->T * sr;
  acc->g += acc->T * sg;
  acc->b += acc->T * sb;
  acc->depth_sum += acc->T * sa * ts;
  acc->T *= (1.0f - sa);
}

// Expected termination depth (conditioned on the ray terminating; 0 where nothing was hit).
LGN_INLINE float march_expected_depth(const MarchAccum* acc) {
  float w = 1.0f - acc->T;
  return w > 1e-6f ? acc->depth_sum / w : 0.0f;
}

// Analytic field at a scene-space point: density summed over the primitives containing it, colour
// the density-weighted mean (0 where the density is 0).
LGN_INLINE void analytic_eval(const AnalyticFieldParams* p, float x, float y, float z, float* sigma,
                              float* rgb) {
  float s = 0.0f, r = 0.0f, g = 0.0f, b = 0.0f;
  for (lgn_uint i = 0; i < p->prim_count && i < LGN_ANALYTIC_MAX_PRIMS; ++i) {
    const AnalyticPrimitive q = p->prims[i];
    int inside;
    if (q.kind == LGN_ANALYTIC_SPHERE) {
      float ex = x - q.a[0], ey = y - q.a[1], ez = z - q.a[2];
      inside = ex * ex + ey * ey + ez * ez <= q.b[0] * q.b[0];
    } else {
      inside = x >= q.a[0] && x <= q.b[0] && y >= q.a[1] && y <= q.b[1] && z >= q.a[2] && z <= q.b[2];
    }
    if (inside) {
      s += q.sigma;
      r += q.sigma * q.rgb[0];
      g += q.sigma * q.rgb[1];
      b += q.sigma * q.rgb[2];
    }
  }
  *sigma = s;
  float inv = s > 0.0f ? 1.0f / s : 0.0f;
  rgb[0] = r * inv;
  rgb[1] = g * inv;
  rgb[2] = b * inv;
}
