// Parameter structs of the training kernels (ray sampling with empty-space skipping, volume
// rendering loss, occupancy-grid point generation) plus the small hash RNG they share; compiles as
// C++ and OpenCL C. Positions handed to the field are normalised to the AABB: (p - min) / extent.
#pragma once
#include "common/cl_compat.h"

#define SAMPLE_MODE_TRAIN 0u  // random pixels over all training images, random background
#define SAMPLE_MODE_VIEW 1u   // consecutive pixels of one camera, fixed background, pixel centres

#define LOSS_L2_SRGB 0u    // squared error on sRGB-encoded colour (what PSNR measures)
#define LOSS_L2_LINEAR 1u  // squared error on linear colour

typedef struct SampleParams {
  float aabb_min[4];     // xyz, scene units (w unused)
  float inv_extent[4];   // 1 / (max - min) per axis
  float bg[4];           // view mode: background rgb (linear)
  float step;            // distance between samples along a ray, scene units
  float near_t;          // samples start at least this far from the camera
  lgn_uint occ_res;      // occupancy grid resolution (cells per axis)
  lgn_uint max_samples;  // per ray
  lgn_uint n_rays;       // rays in this launch
  lgn_uint mode;         // SAMPLE_MODE_*
  lgn_uint camera;       // view mode: camera index
  lgn_uint first_pixel;  // view mode: pixel index of ray 0
  lgn_uint n_images;
  lgn_uint total_pixels;  // train mode: pixels drawn from (all, or the kept ones when n_runs > 0)
  lgn_uint seed;
  lgn_uint iteration;  // training step: selects the random stream
  lgn_uint stride;     // SoA stride of the per-sample arrays (Field::max_batch)
  lgn_uint ray_begin;  // write pass: first ray whose samples are written
  lgn_uint ray_end;    // write pass: one past the last ray written
  // write pass: 1 = the rays also end at batch_info[BATCH_INFO_RAYS] (sample_offsets' fit, computed
  // on the device; ray_begin must be 0); 0 = ray_end alone.
  lgn_uint end_on_device;
  // train mode: runs of kept pixels (host/nerf/kept_pixels.h; pairs of kept index, global pixel) that
  // map a drawn index to its pixel, leaving the views' ignore regions out; 0 = every pixel is kept.
  lgn_uint n_runs;
  lgn_uint pad0, pad1, pad2;
} SampleParams;
LGN_STATIC_ASSERT(sizeof(SampleParams) == 128, "SampleParams layout is shared with OpenCL");

// The batch record sample_offsets writes (uints): the leading rays whose samples fit the batch, their
// samples, the samples of all counted rays, and (written by loss_sum, float bits) the summed loss.
#define BATCH_INFO_RAYS 0u
#define BATCH_INFO_SAMPLES 1u
#define BATCH_INFO_COUNTED 2u
#define BATCH_INFO_LOSS 3u
#define BATCH_INFO_UINTS 4u
// Largest work-group of the single-group scan and sum kernels (their local arrays).
#define BATCH_SCAN_MAX_GROUP 256u

// Per-ray record written by the sampler (floats): target rgb (background composited), background rgb,
// pixel index within its image (as float bits), image index (as float bits), and the background's far
// share: the part of the background colour that a room model's surfaces beyond the subject's
// surroundings give (render_ray_share_beyond; 0 = none known, as the sampler writes it).
#define RAY_INFO_FLOATS 9u
#define RAY_INFO_FAR 8u

// The most skin colours the loss kernel compares a pixel with (LossParams::skin_chroma).
#define SKIN_REFS_MAX 8u

// The share of a skin pixel's light that its sheen may be (train/render.h render_ray_skin_like): skin
// reflects its own colour from below the surface and the light's colour (white, once the camera has balanced
// it) from the surface, so a lit neck's chromaticity lies between the face's and the neutral point
// (dichromatic reflection). 0.3 holds a sheen like the one that moved the dark capture's lit neck
// 11 % of the way from the face's chromaticity to neutral, and a highlight of up to 30 % of the light;
// an off-white wall before pale skin lies about 85 % of the way.
#define SKIN_SHEEN_MAX 0.3f

// The subject's surroundings for render_ray_share_beyond (positions normalised to the room model's box):
// the box [lo, hi], except that below the plane through `base` across `up` (a head box's bottom) only
// points within `base_radius` of the axis through `base` along `up` are near (the neck's base; the
// shoulders beside it are the room's, as the wall is). base_radius <= 0: the whole box.
typedef struct NearRegion {
  float lo[3], hi[3];
  float base[3], up[3];
  float base_radius;
  float pad0;
} NearRegion;

typedef struct LossParams {
  lgn_uint n_rays;
  lgn_uint stride;          // SoA stride of the per-sample arrays
  lgn_uint forward_only;    // 1: colour only (no gradients)
  lgn_uint loss_kind;       // LOSS_*
  float step;               // sample spacing, scene units
  float grad_scale;         // 1 / (3 * rays in the batch): the loss is a mean
  float min_transmittance;  // stop accumulating below this (instant-ngp: 1e-4)
  float opacity_prior;      // weight of the binary-opacity prior (train/render.h); 0 = off
  // Room-explained clearing (train/render.h): the clearing pull relative to opacity_prior where the
  // room's colour matches the pixel (0 = off), and the RMS sRGB difference at which the gate closes.
  float room_clear;
  float room_clear_tolerance;
  // The prior's zones (render_ray_opacity_prior_zones): their bitfields' resolution (0 = none: the
  // ray's gate everywhere), and the least gate in the "lean" zone.
  lgn_uint zone_res;
  float lean_gate;
  float solid_pull;  // the "solid" zone's pull towards an opaque ray, relative to opacity_prior
  // The RMS sRGB margin by which the subject's render nearer the pixel than the room's colour
  // closes the clearing's gate (render_ray_clear_gate; 0 = the room gate alone).
  float subject_explains;
  // The neck's keep zone takes the clearing on rays whose pixel is no skin colour of the subject
  // (render_ray_skin_like): the skin's chromaticities (skin_count pairs of linear r/(r+g+b),
  // g/(r+g+b); 0 = none, the keep zone's binary prior everywhere), the distance within which a pixel
  // matches one, and the luminance under which its chromaticity is not judged.
  lgn_uint skin_count;
  float skin_tolerance;
  float skin_lum_floor;
  // The pull towards an opaque ray of the keep zone's samples within the interior's reach, relative
  // to opacity_prior (0 = off; render_ray_opacity_prior_zones).
  float keep_pull;
  float skin_chroma[2 * SKIN_REFS_MAX];
  // Where samples are near the subject for far_share (render_ray_share_beyond); render_loss does not
  // read it.
  NearRegion near;
} LossParams;
LGN_STATIC_ASSERT(sizeof(NearRegion) == 56, "NearRegion layout is shared with OpenCL");
LGN_STATIC_ASSERT(sizeof(LossParams) == 192, "LossParams layout is shared with OpenCL");

typedef struct OccParams {
  lgn_uint res;
  lgn_uint first_cell;  // entries [first_cell, first_cell + n) of the cell list
  lgn_uint n;
  lgn_uint stride;  // SoA stride of the position array
  lgn_uint seed;
  lgn_uint iteration;  // update counter: new jitter every update
  lgn_uint pad0, pad1;
} OccParams;
LGN_STATIC_ASSERT(sizeof(OccParams) == 32, "OccParams layout is shared with OpenCL");

// PCG hash (Jarzynski & Olano 2020): a stateless counter-based RNG, so every random number is a
// function of (seed, step, ray, k) alone and the result does not depend on work-item scheduling.
LGN_INLINE lgn_uint lgn_pcg(lgn_uint v) {
  lgn_uint state = v * 747796405u + 2891336453u;
  lgn_uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

LGN_INLINE lgn_uint lgn_hash3(lgn_uint a, lgn_uint b, lgn_uint c) {
  return lgn_pcg(a ^ lgn_pcg(b ^ lgn_pcg(c)));
}

// Uniform in [0, 1) from 24 random bits.
LGN_INLINE float lgn_rand01(lgn_uint a, lgn_uint b, lgn_uint c, lgn_uint k) {
  return (float)(lgn_hash3(a, b, c * 16u + k) >> 8) * (1.0f / 16777216.0f);
}
