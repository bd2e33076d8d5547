// Volume rendering of each ray's compacted samples with the loss and its gradient w.r.t. every
// sample's density and colour (one work-item per ray: the standard reverse accumulation of
// train/render.h), or colour only (forward_only) for evaluation renders; and the batch's summed
// loss on the device (loss_sum), so the training step need not read the per-ray losses back.
#include "train/render.h"
#include "train/train_types.h"

__kernel void render_loss(const LossParams p, __global const uint* ray_offsets,
                          __global const uint* ray_counts, __global const float* ray_info,
                          __global const float* sigma, __global const float* rgb, __global float* dsigma,
                          __global float* drgb, __global float* ray_loss, __global float* ray_color,
                          __global const float* pos, __global const uint* zone_bits) {
  uint ray = get_global_id(0);
  if (ray >= p.n_rays) return;
  __global const float* info = ray_info + RAY_INFO_FLOATS * ray;
  float bg[3] = {info[3], info[4], info[5]};
  float target[3] = {info[0], info[1], info[2]};
  float color[4];
  uint first = ray_offsets[ray], count = ray_counts[ray];
  uint used = render_ray_forward(sigma, rgb, p.stride, first, count, p.step, p.min_transmittance, bg, color);
  for (int c = 0; c < 4; ++c) ray_color[4u * ray + (uint)c] = color[c];
  if (p.forward_only) return;
  float dC[3];
  ray_loss[ray] = render_ray_loss(color, target, p.loss_kind, p.grad_scale, dC);
  render_ray_backward(sigma, rgb, p.stride, first, count, used, p.step, color, dC, dsigma, drgb);
  if (p.opacity_prior > 0.0f) {
    const float gate = p.room_clear > 0.0f ? render_ray_clear_gate(target, bg, color, p.room_clear_tolerance,
                                                                   p.subject_explains)
                                           : 0.0f;
    if (p.zone_res > 0u)
      render_ray_opacity_prior_zones(
          first, count, used, p.step, color, p.opacity_prior, p.room_clear, gate,
          render_ray_keep_gate(target, gate, p.skin_chroma, p.skin_count, p.skin_tolerance, p.skin_lum_floor,
                               info[RAY_INFO_FAR]),
          p.keep_pull, p.lean_gate, p.solid_pull, 3.0f * p.grad_scale, pos, p.stride, zone_bits, p.zone_res,
          dsigma);
    else
      render_ray_opacity_prior(first, used, p.step, color, p.opacity_prior, p.room_clear, gate,
                               3.0f * p.grad_scale, dsigma);
  }
}

// The far share of each ray (render_ray_share_beyond over p.near) into share[ray]:
// run on a room model's rays, it tells how much of a subject ray's background lies beyond the
// subject's surroundings (RAY_INFO_FAR).
__kernel void far_share(const LossParams p, __global const uint* ray_offsets, __global const uint* ray_counts,
                        __global const float* sigma, __global const float* pos, __global float* share) {
  const uint ray = get_global_id(0);
  if (ray >= p.n_rays) return;
  const NearRegion near = p.near;
  share[ray] = render_ray_share_beyond(sigma, pos, p.stride, ray_offsets[ray], ray_counts[ray], p.step,
                                       p.min_transmittance, &near);
}

// Sum of ray_loss[0, p.n_rays) into batch_info[BATCH_INFO_LOSS] (float bits). One work-group (local
// size <= BATCH_SCAN_MAX_GROUP): each work-item sums a contiguous chunk in order, then work-item 0
// sums the chunks in order, so for a given group size the result is the same bits on every run.
__kernel void loss_sum(const LossParams p, __global const float* ray_loss, __global uint* batch_info) {
  __local float partial[BATCH_SCAN_MAX_GROUP];
  const uint lid = get_local_id(0), groups = get_local_size(0);
  const uint chunk = (p.n_rays + groups - 1u) / groups;
  const uint begin = min(lid * chunk, p.n_rays), end = min(begin + chunk, p.n_rays);
  float sum = 0.0f;
  for (uint i = begin; i < end; ++i) sum += ray_loss[i];
  partial[lid] = sum;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lid == 0) {
    float total = 0.0f;
    for (uint g = 0; g < groups; ++g) total += partial[g];
    batch_info[BATCH_INFO_LOSS] = as_uint(total);
  }
}
