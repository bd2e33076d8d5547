// The wavefront compositing marcher. Per tile of pixels the host runs:
//   march_init      one ray per pixel: origin, direction, crop to the AABB, surface state
//   loop while rays are live:
//     march_step      each live ray emits up to K segments [t0, t1] through occupied cells,
//                     split exactly at the surface depth t_s (never past an opaque surface)
//     march_scan_*    exclusive prefix sum of the per-ray counts (deterministic, no atomics)
//     march_gather    segment midpoints -> compacted SoA positions (normalised) and directions
//     (field)         sigma, rgb for the compacted samples (NeRF field or analytic_field.cl)
//     march_composite accumulates each ray's segments in order, inserting the surface (Eq. 7,
//                     march_math.h), writes finished rays to the outputs, flags the survivors
//     march_scan_* + march_compact  the live list for the next wave
#include "march/march_math.h"

__kernel void march_init(const MarchParams p, __global MarchRay* rays, __global const float* surf_ca,
                         __global const float* surf_depth, __global uint* live) {
  const uint i = get_global_id(0);
  if (i >= p.ray_count) return;
  rays[i] = march_ray_start(&p, i, surf_ca, surf_depth);
  live[i] = i;
}

// Emits up to K segments for each live ray into its own slots seg[i*K ...] (t0, t1 pairs).
__kernel void march_step(const MarchParams p, __global MarchRay* rays, __global const uint* live,
                         __global const uint* occ, __global uint* counts, __global float2* seg) {
  const uint i = get_global_id(0);
  if (i >= p.live_count) return;
  const uint K = p.samples_per_wave;
  __global MarchRay* r = rays + live[i];
  float t = r->t;
  const float t_end = r->t_end;
  const float ts = r->surface == LGN_SURF_PENDING ? r->t_surface : INFINITY;
  const float ox = r->ox, oy = r->oy, oz = r->oz, dx = r->dx, dy = r->dy, dz = r->dz;
  uint n = 0;
  uint budget = p.max_samples > r->samples ? p.max_samples - r->samples : 0u;
  // Skipping empty cells costs iterations too; bound them so one wave stays short.
  for (uint iter = 0; iter < K + 3u * p.occ_res + 4u && n + 2u <= K && t < t_end; ++iter) {
    if (n >= budget) {
      t = t_end;  // safety bound reached: the ray ends here
      break;
    }
    float tm = fmin(t + 0.5f * p.step, 0.5f * (t + t_end));  // the sample point of this segment
    if (!march_occupied(p.occ_layout, p.occ_res, occ, p.aabb_min, p.aabb_max, ox + tm * dx, oy + tm * dy,
                        oz + tm * dz)) {
      t += march_skip(p.aabb_min, p.aabb_max, p.occ_res, p.step, tm, ox, oy, oz, dx, dy, dz);
      continue;
    }
    float t1 = fmin(t + p.step, t_end);
    if (ts > t && ts < t1) {  // the surface lies inside this step: split it exactly there
      seg[i * K + n++] = (float2)(t, ts);
      seg[i * K + n++] = (float2)(ts, t1);
    } else {
      seg[i * K + n++] = (float2)(t, t1);
    }
    t = t1;
  }
  r->t = fmin(t, t_end);
  counts[i] = n;
}

// Exclusive prefix sum in three deterministic passes: per-block sums (one work-item per block of
// `block` entries), a single work-item scan of the block sums (writes the total), then per block.
__kernel void march_scan_blocks(const uint n, const uint block, __global const uint* in,
                                __global uint* block_sums) {
  const uint b = get_global_id(0);
  const uint begin = b * block;
  if (begin >= n) return;
  const uint end = min(begin + block, n);
  uint s = 0;
  for (uint k = begin; k < end; ++k) s += in[k];
  block_sums[b] = s;
}

__kernel void march_scan_top(const uint nblocks, __global uint* block_sums, __global uint* total) {
  if (get_global_id(0) != 0) return;
  uint s = 0;
  for (uint b = 0; b < nblocks; ++b) {
    uint v = block_sums[b];
    block_sums[b] = s;
    s += v;
  }
  total[0] = s;
}

__kernel void march_scan_apply(const uint n, const uint block, __global const uint* in,
                               __global const uint* block_sums, __global uint* out) {
  const uint b = get_global_id(0);
  const uint begin = b * block;
  if (begin >= n) return;
  const uint end = min(begin + block, n);
  uint s = block_sums[b];
  for (uint k = begin; k < end; ++k) {
    uint v = in[k];
    out[k] = s;
    s += v;
  }
}

// Keeps the live entries whose flag is set, in order.
__kernel void march_compact(const uint n, __global const uint* flags, __global const uint* offsets,
                            __global const uint* live_in, __global uint* live_out) {
  const uint i = get_global_id(0);
  if (i >= n || !flags[i]) return;
  live_out[offsets[i]] = live_in[i];
}

// Segment midpoints of every live ray into the field's compacted SoA inputs (positions normalised
// to the AABB, unit directions), at the ray's offset from the scan.
__kernel void march_gather(const MarchParams p, __global const MarchRay* rays, __global const uint* live,
                           __global const uint* counts, __global const uint* offsets,
                           __global const float2* seg, __global float* pos, __global float* dir) {
  const uint i = get_global_id(0);
  if (i >= p.live_count) return;
  const MarchRay r = rays[live[i]];
  const uint K = p.samples_per_wave, S = p.field_stride, n = counts[i], off = offsets[i];
  for (uint k = 0; k < n; ++k) {
    float2 s = seg[i * K + k];
    float q[3];
    march_sample_position(p.aabb_min, p.aabb_max, r.ox, r.oy, r.oz, r.dx, r.dy, r.dz, 0.5f * (s.x + s.y), q);
    uint j = off + k;
    pos[j] = q[0];
    pos[S + j] = q[1];
    pos[2 * S + j] = q[2];
    dir[j] = r.dx;
    dir[S + j] = r.dy;
    dir[2 * S + j] = r.dz;
  }
}

LGN_INLINE void march_add_pixel_surface(MarchAccum* acc, float ts, __global const float* ca) {
  march_add_surface(acc, ts, ca[0], ca[1], ca[2], ca[3]);
}

// Accumulates each live ray's segments in order, inserting the surface before the first segment
// that starts at or behind t_s; finished rays are written out, flags[i] = 1 for survivors.
__kernel void march_composite(const MarchParams p, __global MarchRay* rays, __global const uint* live,
                              __global const uint* counts, __global const uint* offsets,
                              __global const float2* seg, __global const float* sigma,
                              __global const float* rgb, __global const float* surf_ca,
                              __global const float* surf_filter, __global float* out_rgba,
                              __global float* out_depth, __global uint* out_samples, __global uint* flags) {
  const uint i = get_global_id(0);
  if (i >= p.live_count) return;
  __global MarchRay* r = rays + live[i];
  MarchAccum acc = {r->transmittance, r->r, r->g, r->b, r->depth_sum};
  const uint K = p.samples_per_wave, S = p.field_stride, n = counts[i], off = offsets[i];
  uint surface = r->surface, samples = r->samples;
  const float ts = r->t_surface;
  __global const float* ca = surf_ca + 4 * r->pixel;
  __global const float* fl = surf_filter + 3 * r->pixel;
  float f[3] = {1.0f, 1.0f, 1.0f};  // colour filter of the surface once passed
  if (surface == LGN_SURF_PASSED) f[0] = fl[0], f[1] = fl[1], f[2] = fl[2];
  int done = 0;
  for (uint k = 0; k < n && !done; ++k) {
    float2 s = seg[i * K + k];
    if (surface == LGN_SURF_PENDING && s.x >= ts) {
      march_add_pixel_surface(&acc, ts, ca);
      surface = LGN_SURF_PASSED;
      f[0] = fl[0], f[1] = fl[1], f[2] = fl[2];
      if (acc.T < p.min_transmittance) {
        done = 1;
        break;
      }
    }
    uint j = off + k;
    march_add_segment(&acc, s.x, s.y, sigma[j], f[0] * rgb[j], f[1] * rgb[S + j], f[2] * rgb[2 * S + j]);
    ++samples;
    if (acc.T < p.min_transmittance) done = 1;
  }
  if (!done && r->t >= r->t_end) {  // the march is over: a surface behind it still shows
    if (surface == LGN_SURF_PENDING) {
      march_add_pixel_surface(&acc, ts, ca);
      surface = LGN_SURF_PASSED;
      f[0] = fl[0], f[1] = fl[1], f[2] = fl[2];
    }
    done = 1;
  }
  r->transmittance = acc.T;
  r->r = acc.r;
  r->g = acc.g;
  r->b = acc.b;
  r->depth_sum = acc.depth_sum;
  r->samples = samples;
  r->surface = surface;
  if (done) march_write_pixel(&p, &acc, f, r->pixel, samples, out_rgba, out_depth, out_samples);
  flags[i] = done ? 0u : 1u;
}
