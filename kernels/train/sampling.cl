// Ray sampling with empty-space skipping, in two deterministic passes: sample_count marches every
// ray and stores how many samples it takes; the counts become offsets (prefix sum: sample_offsets on
// the device, which also finds the leading rays that fit the batch, or the host); sample_write
// marches the same rays again and writes each sample at its ray's offset. No atomics, so the
// compacted order is the ray order whatever the scheduling.
//
// Rays: SAMPLE_MODE_TRAIN picks pixels uniformly over all training images (counter-based RNG on
// seed, iteration, ray) but those in ignore regions (drawn over the kept pixels, mapped through
// their runs), jitters them inside the pixel and composites the RGBA target onto a
// random background colour (instant-ngp's trick, so transparency is learnt); SAMPLE_MODE_VIEW takes
// consecutive pixel centres of one camera. Samples are `step` apart from a (jittered) start, only
// inside the AABB and only in occupied cells; empty cells are jumped over to the next sample
// position past the cell's exit.
#include "common/camera_types.h"
#include "train/occupancy.h"
#include "train/train_types.h"

typedef struct RaySetup {
  float o[3], d[3];
  float t_start, t_end;
  float target[3], bg[3];
  uint image, pixel;
} RaySetup;

// Image holding a global pixel index: the largest i with offsets[i] <= pixel.
uint find_image(__global const uint* offsets, uint n_images, uint pixel) {
  uint lo = 0, hi = n_images;  // offsets[lo] <= pixel < offsets[hi]
  while (hi - lo > 1u) {
    uint mid = (lo + hi) / 2u;
    if (offsets[mid] <= pixel)
      lo = mid;
    else
      hi = mid;
  }
  return lo;
}

// Global pixel of kept index k: runs holds n_runs pairs (first kept index, first global pixel), sorted;
// the run holding k is the last whose first kept index is <= k.
uint kept_to_global(__global const uint* runs, uint n_runs, uint k) {
  uint lo = 0, hi = n_runs;  // runs[2 lo] <= k < runs[2 hi]
  while (hi - lo > 1u) {
    uint mid = (lo + hi) / 2u;
    if (runs[2u * mid] <= k)
      lo = mid;
    else
      hi = mid;
  }
  return runs[2u * lo + 1u] + (k - runs[2u * lo]);
}

// Clips the ray to the AABB; returns 0 when it misses.
int clip_aabb(const SampleParams* p, RaySetup* r, float t_min) {
  float t0 = t_min, t1 = 3.0e38f;
  for (int a = 0; a < 3; ++a) {
    float lo = p->aabb_min[a], hi = lo + 1.0f / p->inv_extent[a];
    float inv = 1.0f / r->d[a];  // +-inf for a zero component: the comparisons below still work
    float ta = (lo - r->o[a]) * inv, tb = (hi - r->o[a]) * inv;
    if (r->d[a] == 0.0f) {
      if (r->o[a] < lo || r->o[a] > hi) return 0;
      continue;
    }
    t0 = fmax(t0, fmin(ta, tb));
    t1 = fmin(t1, fmax(ta, tb));
  }
  r->t_start = t0;
  r->t_end = t1;
  return t1 > t0;
}

int setup_ray(const SampleParams* p, __global const Camera* cams, __global const uint* offsets,
              __global const float* pixels, __global const uint* runs, uint ray, RaySetup* r) {
  Camera cam;
  float u, v, jitter;
  if (p->mode == SAMPLE_MODE_TRAIN) {
    uint h = lgn_hash3(p->seed, p->iteration, ray * 8u);
    uint global_pixel = (uint)(((ulong)h * (ulong)p->total_pixels) >> 32);
    if (p->n_runs > 0u) global_pixel = kept_to_global(runs, p->n_runs, global_pixel);
    r->image = find_image(offsets, p->n_images, global_pixel);
    r->pixel = global_pixel - offsets[r->image];
    cam = cams[r->image];
    u = (float)(r->pixel % cam.width) + lgn_rand01(p->seed, p->iteration, ray, 1u);
    v = (float)(r->pixel / cam.width) + lgn_rand01(p->seed, p->iteration, ray, 2u);
    jitter = lgn_rand01(p->seed, p->iteration, ray, 3u);
    __global const float* px = pixels + 4u * global_pixel;
    for (int c = 0; c < 3; ++c) {
      r->bg[c] = lgn_rand01(p->seed, p->iteration, ray, 4u + (uint)c);
      r->target[c] = px[c] * px[3] + r->bg[c] * (1.0f - px[3]);
    }
  } else {
    r->image = p->camera;
    r->pixel = p->first_pixel + ray;
    cam = cams[r->image];
    u = (float)(r->pixel % cam.width) + 0.5f;
    v = (float)(r->pixel / cam.width) + 0.5f;
    jitter = 0.5f;
    for (int c = 0; c < 3; ++c) {
      r->bg[c] = p->bg[c];
      r->target[c] = 0.0f;
    }
  }
  LgnVec3 o = camera_origin(&cam), d = camera_ray_dir(&cam, u, v);
  r->o[0] = o.x;
  r->o[1] = o.y;
  r->o[2] = o.z;
  r->d[0] = d.x;
  r->d[1] = d.y;
  r->d[2] = d.z;
  if (!clip_aabb(p, r, p->near_t)) return 0;
  r->t_start += jitter * p->step;
  return r->t_start < r->t_end;
}

// Marches one ray; when `write` is set, stores its samples from index `out` on (SoA, stride).
uint march_ray(const SampleParams* p, __global const uint* occ, const RaySetup* r, int write, uint out,
               __global float* pos, __global float* dir) {
  float dn[3], q[3];
  for (int a = 0; a < 3; ++a) dn[a] = r->d[a] * p->inv_extent[a];
  float t = r->t_start;
  uint n = 0;
  while (t < r->t_end && n < p->max_samples) {
    for (int a = 0; a < 3; ++a) q[a] = (r->o[a] + t * r->d[a] - p->aabb_min[a]) * p->inv_extent[a];
    lgn_int cell = occ_cell_index(p->occ_res, q[0], q[1], q[2]);
    if (occ_cell_occupied(occ, cell)) {
      if (write) {
        uint i = out + n;
        for (int a = 0; a < 3; ++a) {
          pos[(uint)a * p->stride + i] = clamp(q[a], 0.0f, 1.0f);
          dir[(uint)a * p->stride + i] = r->d[a];
        }
      }
      ++n;
      t += p->step;
    } else {
      float skip = occ_cell_exit(p->occ_res, q[0], q[1], q[2], dn[0], dn[1], dn[2]);
      t += p->step * fmax(ceil(skip / p->step), 1.0f);
    }
  }
  return n;
}

__kernel void sample_count(const SampleParams p, __global const Camera* cams, __global const uint* offsets,
                           __global const float* pixels, __global const uint* runs, __global const uint* occ,
                           __global uint* counts) {
  uint ray = get_global_id(0);
  if (ray >= p.n_rays) return;
  RaySetup r;
  counts[ray] =
      setup_ray(&p, cams, offsets, pixels, runs, ray, &r) ? march_ray(&p, occ, &r, 0, 0u, 0, 0) : 0u;
}

// Exclusive prefix sum of counts[0, n_rays) into ray_offsets, and the batch record (train_types.h):
// the leading rays whose samples total at most `budget` (= p.stride, the field's batch), their
// samples and the total of all counts. One work-group (local size <= BATCH_SCAN_MAX_GROUP): each
// work-item scans a contiguous chunk; integer sums, so the result is exact whatever the group size.
__kernel void sample_offsets(const SampleParams p, __global const uint* counts, __global uint* ray_offsets,
                             __global uint* batch_info) {
  __local uint base[BATCH_SCAN_MAX_GROUP];
  __local uint fits[BATCH_SCAN_MAX_GROUP];
  const uint lid = get_local_id(0), groups = get_local_size(0);
  const uint chunk = (p.n_rays + groups - 1u) / groups;
  const uint begin = min(lid * chunk, p.n_rays), end = min(begin + chunk, p.n_rays);
  uint sum = 0;
  for (uint i = begin; i < end; ++i) sum += counts[i];
  base[lid] = sum;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lid == 0) {
    uint run = 0;
    for (uint g = 0; g < groups; ++g) {
      const uint s = base[g];
      base[g] = run;
      run += s;
    }
    batch_info[BATCH_INFO_COUNTED] = run;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  uint run = base[lid], n_fit = 0, fit_samples = 0;
  for (uint i = begin; i < end; ++i) {
    ray_offsets[i] = run;
    run += counts[i];
    if (run <= p.stride) {  // inclusive sums only grow: the rays that fit are a prefix
      ++n_fit;
      fit_samples = run;
    }
  }
  fits[lid] = n_fit;
  base[lid] = fit_samples;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lid == 0) {
    uint rays = 0, samples = 0;
    for (uint g = 0; g < groups; ++g) {
      rays += fits[g];
      if (fits[g]) samples = base[g];
    }
    batch_info[BATCH_INFO_RAYS] = rays;
    batch_info[BATCH_INFO_SAMPLES] = samples;
  }
}

// Rays [ray_begin, ray_end) (and below batch_info[BATCH_INFO_RAYS] when p.end_on_device): sample
// offsets come relative to ray_begin; ray_info gets RAY_INFO_FLOATS floats per ray (target rgb,
// background rgb, pixel, image, a far share of 0).
__kernel void sample_write(const SampleParams p, __global const Camera* cams, __global const uint* offsets,
                           __global const float* pixels, __global const uint* runs, __global const uint* occ,
                           __global const uint* ray_offsets, __global const uint* batch_info,
                           __global float* pos, __global float* dir, __global float* ray_info) {
  uint ray = p.ray_begin + get_global_id(0);
  if (ray >= p.ray_end || (p.end_on_device && ray >= batch_info[BATCH_INFO_RAYS])) return;
  uint local_ray = ray - p.ray_begin;
  RaySetup r;
  if (setup_ray(&p, cams, offsets, pixels, runs, ray, &r))
    march_ray(&p, occ, &r, 1, ray_offsets[local_ray], pos, dir);
  __global float* info = ray_info + RAY_INFO_FLOATS * local_ray;
  for (int c = 0; c < 3; ++c) {
    info[c] = r.target[c];
    info[3 + c] = r.bg[c];
  }
  info[6] = as_float(r.pixel);
  info[7] = as_float(r.image);
  info[RAY_INFO_FAR] = 0.0f;
}
