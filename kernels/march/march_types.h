// Parameter structs of the compositing marcher (kernels/march/*.cl), shared by host and kernels:
// MarchParams drives one wavefront pass (camera, crop box, step, occupancy grid, surface buffers,
// output mode), MarchRay is the per-ray state that persists between waves, and
// AnalyticFieldParams describes the analytic density/colour fields that tests and benchmarks use
// in place of the NeRF field. Fixed-width scalars only (see kernels/common/cl_compat.h).
#pragma once
#include "common/camera_types.h"
#include "common/cl_compat.h"

// Occupancy layouts the marcher understands (MarchParams.occ_layout).
#define LGN_MARCH_OCC_NONE 0    // every cell occupied (analytic fields without a grid)
#define LGN_MARCH_OCC_LINEAR 1  // the NeRF grid: res^3 bits over the AABB (train/occupancy.h rule)

typedef struct MarchParams {
  Camera cam;
  float aabb_min[3];
  float aabb_max[3];
  float step;                // marching step along the unit ray, scene units
  float min_transmittance;   // a ray stops once T falls below this (1e-4)
  float background[3];       // linear RGB added behind the volume when alpha_mode == 0
  float sample_weight;       // 1 / spp: each sub-pixel pass adds this share to the outputs
  float jitter_u, jitter_v;  // sub-pixel offset of this pass (0.5, 0.5 = pixel centre)
  lgn_uint alpha_mode;       // 1: no background, rgb premultiplied by alpha = 1 - T
  lgn_uint has_surface;      // 1: surface buffers are bound
  lgn_uint occ_layout;       // LGN_MARCH_OCC_*
  lgn_uint occ_res;          // cells per axis
  lgn_uint ray_begin;        // first pixel of this tile (rays are pixels ray_begin..+ray_count)
  lgn_uint ray_count;
  lgn_uint max_samples;       // per ray and pass; the march ends there (a safety bound)
  lgn_uint field_stride;      // structure-of-arrays stride of the field's sample buffers
  lgn_uint samples_per_wave;  // K: segments one march_step may emit per ray
  lgn_uint live_count;        // rays in the live list for this wave
} MarchParams;

LGN_STATIC_ASSERT(sizeof(MarchParams) == sizeof(Camera) + 4 * 14 + 4 * 10,
                  "MarchParams layout is shared with OpenCL");

// Surface compositing state of a ray (MarchRay.surface).
#define LGN_SURF_NONE 0     // no surface on this ray (or already composited)
#define LGN_SURF_PENDING 1  // the surface at t_s is still ahead of the march
#define LGN_SURF_PASSED 2   // composited: what follows is seen through its colour filter F

typedef struct MarchRay {
  float ox, oy, oz;     // origin
  float dx, dy, dz;     // unit direction
  float t;              // march position: everything before t has been emitted
  float t_end;          // end of the march: AABB exit, or the opaque surface's depth
  float t_surface;      // S_t (scene units along the unit ray)
  float transmittance;  // T accumulated so far
  float r, g, b;        // accumulated colour (premultiplied)
  float depth_sum;      // sum of weight * depth
  lgn_uint pixel;       // index into the image
  lgn_uint samples;     // segments composited so far
  lgn_uint surface;     // LGN_SURF_*
  lgn_uint pad;
} MarchRay;

LGN_STATIC_ASSERT(sizeof(MarchRay) == 72, "MarchRay layout is shared with OpenCL");

// Analytic fields: up to 4 constant-density primitives (axis-aligned boxes or spheres), density
// summed, colour the density-weighted mean. Defined in scene units; the field receives positions
// normalised to the AABB (as the NeRF field does) and maps them back.
#define LGN_ANALYTIC_BOX 0
#define LGN_ANALYTIC_SPHERE 1
#define LGN_ANALYTIC_MAX_PRIMS 4

typedef struct AnalyticPrimitive {
  lgn_uint kind;  // LGN_ANALYTIC_BOX: a = min, b = max; LGN_ANALYTIC_SPHERE: a = centre, b[0] = radius
  float sigma;    // density inside
  float rgb[3];   // colour inside, [0, 1]
  float a[3], b[3];
  lgn_uint pad;
} AnalyticPrimitive;

typedef struct AnalyticFieldParams {
  float aabb_min[3];
  float aabb_max[3];
  lgn_uint prim_count;
  lgn_uint stride;  // structure-of-arrays stride of the sample buffers
  lgn_uint count;   // samples to evaluate
  lgn_uint pad[3];
  AnalyticPrimitive prims[LGN_ANALYTIC_MAX_PRIMS];
} AnalyticFieldParams;

LGN_STATIC_ASSERT(sizeof(AnalyticPrimitive) == 48, "AnalyticPrimitive layout is shared with OpenCL");
LGN_STATIC_ASSERT(sizeof(AnalyticFieldParams) == 48 + 4 * 48, "AnalyticFieldParams layout");
