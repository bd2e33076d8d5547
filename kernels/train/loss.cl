// Volume rendering of each ray's compacted samples with the loss and its gradient w.r.t. every
// sample's density and colour (one work-item per ray: the standard reverse accumulation of
// train/render.h), or colour only (forward_only) for evaluation renders.
#include "train/render.h"
#include "train/train_types.h"

__kernel void render_loss(const LossParams p, __global const uint* ray_offsets, __global const uint* ray_counts,
                          __global const float* ray_info, __global const float* sigma,
                          __global const float* rgb, __global float* dsigma, __global float* drgb,
                          __global float* ray_loss, __global float* ray_color) {
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
  if (p.opacity_prior > 0.0f)
    render_ray_opacity_prior(first, used, p.step, color, p.opacity_prior, 3.0f * p.grad_scale, dsigma);
}
