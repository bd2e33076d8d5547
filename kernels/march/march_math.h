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
using std::isfinite;
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

// The ray of pixel p->ray_begin + i (sub-pixel p->jitter_u/v): origin, unit direction, its span in
// the crop box (empty when it misses), and the surface it meets (S_t, pending when S_α > 0; an opaque
// surface ends the march at S_t). Nothing accumulated yet. Both marchers start their rays here.
LGN_INLINE MarchRay march_ray_start(const MarchParams* p, lgn_uint i, LGN_GLOBAL const float* surf_ca,
                                    LGN_GLOBAL const float* surf_depth) {
  const lgn_uint pixel = p->ray_begin + i;
  const lgn_uint px = pixel % p->cam.width, py = pixel / p->cam.width;
  LgnVec3 d = camera_ray_dir(&p->cam, (float)px + p->jitter_u, (float)py + p->jitter_v);
  LgnVec3 o = camera_origin(&p->cam);
  MarchRay r;
  r.ox = o.x;
  r.oy = o.y;
  r.oz = o.z;
  r.dx = d.x;
  r.dy = d.y;
  r.dz = d.z;
  float t0, t1;
  if (!march_clip_aabb(p->aabb_min, p->aabb_max, o.x, o.y, o.z, d.x, d.y, d.z, &t0, &t1)) t0 = t1 = 0.0f;
  r.t = t0;
  r.t_end = t1;
  r.t_surface = LGN_MARCH_INF;
  r.surface = LGN_SURF_NONE;
  if (p->has_surface) {
    float sa = surf_ca[4 * pixel + 3];
    float ts = surf_depth[pixel];
    if (sa > 0.0f && isfinite(ts) && ts > 0.0f) {
      r.surface = LGN_SURF_PENDING;
      r.t_surface = ts;
      if (sa >= 1.0f) r.t_end = fmin(r.t_end, ts);  // nothing behind an opaque surface is visible
    }
  }
  r.transmittance = 1.0f;
  r.r = r.g = r.b = 0.0f;
  r.depth_sum = 0.0f;
  r.pixel = pixel;
  r.samples = 0;
  r.pad = 0;
  return r;
}

// The field's input for the segment midpoint tm of a ray: the point normalised to the crop box.
LGN_INLINE void march_sample_position(const float* bmin, const float* bmax, float ox, float oy, float oz,
                                      float dx, float dy, float dz, float tm, float* pos) {
  pos[0] = (ox + tm * dx - bmin[0]) / (bmax[0] - bmin[0]);
  pos[1] = (oy + tm * dy - bmin[1]) / (bmax[1] - bmin[1]);
  pos[2] = (oz + tm * dz - bmin[2]) / (bmax[2] - bmin[2]);
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

// Writes a finished ray into the outputs (each pass adds its sample_weight share); the background
// is seen through the surface's colour filter f.
LGN_INLINE void march_write_pixel(const MarchParams* p, const MarchAccum* acc, const float* f, lgn_uint pixel,
                                  lgn_uint samples, LGN_GLOBAL float* out_rgba, LGN_GLOBAL float* out_depth,
                                  LGN_GLOBAL lgn_uint* out_samples) {
  const float w = p->sample_weight;
  const float bg = p->alpha_mode ? 0.0f : 1.0f;
  out_rgba[4 * pixel + 0] += w * (acc->r + bg * acc->T * f[0] * p->background[0]);
  out_rgba[4 * pixel + 1] += w * (acc->g + bg * acc->T * f[1] * p->background[1]);
  out_rgba[4 * pixel + 2] += w * (acc->b + bg * acc->T * f[2] * p->background[2]);
  out_rgba[4 * pixel + 3] += w * (1.0f - acc->T);
  out_depth[pixel] += w * march_expected_depth(acc);
  out_samples[pixel] += samples;
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

// The analytic field at a position normalised to its box (the field's interface, as the marchers
// pass it): mapped back to scene units, then analytic_eval.
LGN_INLINE void analytic_eval_normalised(const AnalyticFieldParams* p, const float* pos, float* sigma,
                                         float* rgb) {
  analytic_eval(p, p->aabb_min[0] + pos[0] * (p->aabb_max[0] - p->aabb_min[0]),
                p->aabb_min[1] + pos[1] * (p->aabb_max[1] - p->aabb_min[1]),
                p->aabb_min[2] + pos[2] * (p->aabb_max[2] - p->aabb_min[2]), sigma, rgb);
}
