// RayBatch: drives kernels/train/sampling.cl and loss.cl for one batch of rays.
#include "host/nerf/ray_batch.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace lorgnette::nerf {
namespace {
// Rays per work-group of the sampling and loss kernels (one work-item per ray): whole warps on a
// GPU; 16 on a CPU, so a 2^16 step's ~2,300 rays make ~150 groups instead of 36 for PoCL's threads
// to balance (ray lengths differ widely with empty-space skipping).
size_t ray_group(const cl::Runtime& rt) { return rt.device().is_gpu ? 64 : 16; }
// The single work-group of sample_offsets and loss_sum: a GPU scans with 256 work-items, a CPU with
// one (a few thousand additions; one work-item avoids PoCL's barrier loops).
size_t scan_group(const cl::Runtime& rt) { return rt.device().is_gpu ? BATCH_SCAN_MAX_GROUP : 1; }
}  // namespace

SampleParams sample_params_for(const NerfModel& model, const DeviceViews& views) {
  SampleParams p{};
  const Aabb& box = model.aabb();
  for (int a = 0; a < 3; ++a) {
    p.aabb_min[a] = box.min[a];
    p.inv_extent[a] = 1.0f / box.extent(a);
  }
  p.step = model.step();
  p.near_t = 0.0f;
  p.occ_res = model.occupancy_resolution();
  p.max_samples = std::min(model.max_samples_per_ray(), model.field().max_batch());
  p.n_images = views.count();
  p.total_pixels = static_cast<uint32_t>(views.sampled_pixels());
  p.n_runs = views.run_count();
  p.stride = model.field().max_batch();
  return p;
}

RayBatch::RayBatch(NerfModel& model, uint32_t max_rays)
    : model_(model), max_rays_(max_rays), stride_(model.field().max_batch()) {
  cl::Runtime& rt = model.runtime();
  cl_program sampling = rt.program("train/sampling.cl");
  count_k_ = cl::Kernel(sampling, "sample_count");
  offsets_k_ = cl::Kernel(sampling, "sample_offsets");
  write_k_ = cl::Kernel(sampling, "sample_write");
  cl_program loss = rt.program("train/loss.cl");
  render_k_ = cl::Kernel(loss, "render_loss");
  loss_sum_k_ = cl::Kernel(loss, "loss_sum");
  far_k_ = cl::Kernel(loss, "far_share");
  batch_info_ = cl::Buffer<uint32_t>(rt, BATCH_INFO_UINTS);
  batch_info_.fill(rt, 0u);
  counts_dev_ = cl::Buffer<uint32_t>(rt, max_rays);
  sub_offsets_ = cl::Buffer<uint32_t>(rt, max_rays);
  sub_counts_ = cl::Buffer<uint32_t>(rt, max_rays);
  ray_info_ = cl::Buffer<float>(rt, size_t(max_rays) * RAY_INFO_FLOATS);
  ray_loss_ = cl::Buffer<float>(rt, max_rays);
  ray_share_ = cl::Buffer<float>(rt, max_rays);
  ray_color_ = cl::Buffer<float>(rt, size_t(max_rays) * 4);
  pos_ = cl::Buffer<float>(rt, size_t(stride_) * 3);
  dir_ = cl::Buffer<float>(rt, size_t(stride_) * 3);
  sigma_ = cl::Buffer<float>(rt, stride_);
  rgb_ = cl::Buffer<float>(rt, size_t(stride_) * 3);
  dsigma_ = cl::Buffer<float>(rt, stride_);
  drgb_ = cl::Buffer<float>(rt, size_t(stride_) * 3);
  no_zones_ = cl::Buffer<uint32_t>(rt, 1);
  no_zones_.fill(rt, 0u);
}

const std::vector<uint32_t>& RayBatch::count(const SampleParams& p, const DeviceViews& views) {
  if (p.n_rays > max_rays_)
    throw std::invalid_argument(
        fmt::format("RayBatch::count: {} rays exceed the capacity {}", p.n_rays, max_rays_));
  cl::Runtime& rt = model_.runtime();
  if (p.n_rays > 0) {
    count_k_
        .args(p, views.camera_buffer(), views.offsets(), views.pixels(), views.kept_runs(),
              model_.occupancy_bits(), counts_dev_)
        .launch(rt, p.n_rays, ray_group(rt));
  }
  counts_ = counts_dev_.read(rt, p.n_rays);
  return counts_;
}

uint32_t RayBatch::fit(uint32_t begin, uint32_t budget) const {
  uint64_t total = 0;
  uint32_t end = begin;
  while (end < counts_.size() && total + counts_[end] <= budget) total += counts_[end++];
  return end;
}

uint32_t RayBatch::write(SampleParams p, const DeviceViews& views, uint32_t begin, uint32_t end) {
  if (end > counts_.size() || begin > end)
    throw std::out_of_range("RayBatch::write: ray range outside the counted rays");
  cl::Runtime& rt = model_.runtime();
  uint32_t n = end - begin;
  std::vector<uint32_t> offsets(n), counts(counts_.begin() + begin, counts_.begin() + end);
  uint64_t total = 0;
  for (uint32_t i = 0; i < n; ++i) {
    offsets[i] = static_cast<uint32_t>(total);
    total += counts[i];
  }
  if (total > stride_)
    throw std::out_of_range(fmt::format("RayBatch::write: {} samples exceed the batch {}", total, stride_));
  written_rays_ = n;
  written_samples_ = static_cast<uint32_t>(total);
  on_device_ = false;
  if (n == 0) return 0;
  sub_offsets_.write(rt, offsets);
  sub_counts_.write(rt, counts);
  p.ray_begin = begin;
  p.ray_end = end;
  p.end_on_device = 0;
  write_k_
      .args(p, views.camera_buffer(), views.offsets(), views.pixels(), views.kept_runs(),
            model_.occupancy_bits(), sub_offsets_, batch_info_, pos_, dir_, ray_info_)
      .launch(rt, n, ray_group(rt));
  return written_samples_;
}

RayBatch::DeviceBatch RayBatch::sample_on_device(SampleParams p, const DeviceViews& views) {
  if (p.n_rays > max_rays_)
    throw std::invalid_argument(
        fmt::format("RayBatch::sample_on_device: {} rays exceed the capacity {}", p.n_rays, max_rays_));
  if (p.max_samples > stride_)
    throw std::invalid_argument(fmt::format(
        "RayBatch::sample_on_device: {} samples per ray exceed the batch {}", p.max_samples, stride_));
  cl::Runtime& rt = model_.runtime();
  p.stride = stride_;  // the budget of sample_offsets' fit
  p.ray_begin = 0;
  p.ray_end = p.n_rays;
  p.end_on_device = 1;
  if (p.n_rays > 0) {
    count_k_
        .args(p, views.camera_buffer(), views.offsets(), views.pixels(), views.kept_runs(),
              model_.occupancy_bits(), counts_dev_)
        .launch(rt, p.n_rays, ray_group(rt));
    const size_t group = scan_group(rt);
    offsets_k_.args(p, counts_dev_, sub_offsets_, batch_info_).launch(rt, group, group);
    write_k_
        .args(p, views.camera_buffer(), views.offsets(), views.pixels(), views.kept_runs(),
              model_.occupancy_bits(), sub_offsets_, batch_info_, pos_, dir_, ray_info_)
        .launch(rt, p.n_rays, ray_group(rt));
  }
  uint32_t info[BATCH_INFO_UINTS];
  batch_info_.read(rt, info, BATCH_INFO_UINTS);
  DeviceBatch b;
  if (p.n_rays > 0) {
    b.rays = info[BATCH_INFO_RAYS];
    b.samples = info[BATCH_INFO_SAMPLES];
    b.counted = info[BATCH_INFO_COUNTED];
  }
  std::memcpy(&b.previous_loss_sum, &info[BATCH_INFO_LOSS], sizeof(float));
  written_rays_ = b.rays;
  written_samples_ = b.samples;
  on_device_ = true;
  counts_.clear();  // the host way's counts no longer describe the written rays
  return b;
}

void RayBatch::render_on_device(uint32_t loss_kind, float min_transmittance, const RayPriors& priors) {
  if (!on_device_) throw std::logic_error("RayBatch::render_on_device must follow sample_on_device");
  if (written_rays_ == 0) return;
  cl::Runtime& rt = model_.runtime();
  LossParams lp = loss_params(loss_kind, false, min_transmittance, priors);
  render_k_
      .args(lp, sub_offsets_, counts_dev_, ray_info_, sigma_, rgb_, dsigma_, drgb_, ray_loss_, ray_color_,
            pos_, priors.zones ? *priors.zones : no_zones_)
      .launch(rt, written_rays_, ray_group(rt));
  const size_t group = scan_group(rt);
  loss_sum_k_.args(lp, ray_loss_, batch_info_).launch(rt, group, group);
}

float RayBatch::loss_sum() const {
  uint32_t bits = 0;
  batch_info_.read(model_.runtime(), &bits, 1, BATCH_INFO_LOSS);
  float sum;
  std::memcpy(&sum, &bits, sizeof(float));
  return sum;
}

LossParams RayBatch::loss_params(uint32_t loss_kind, bool forward_only, float min_transmittance,
                                 const RayPriors& priors) const {
  LossParams lp{};
  lp.n_rays = written_rays_;
  lp.stride = stride_;
  lp.forward_only = forward_only ? 1u : 0u;
  lp.loss_kind = loss_kind;
  lp.step = model_.step();
  lp.grad_scale = 1.0f / (3.0f * float(written_rays_));
  lp.min_transmittance = min_transmittance;
  lp.opacity_prior = priors.weight;
  lp.room_clear = priors.room_clear;
  lp.room_clear_tolerance = priors.room_clear_tolerance;
  lp.subject_explains = priors.subject_explains;
  lp.zone_res = priors.zones ? priors.zone_res : 0u;
  lp.lean_gate = priors.zones ? priors.lean_gate : 0.0f;
  lp.solid_pull = priors.zones ? priors.solid_pull : 0.0f;
  lp.keep_pull = priors.zones ? priors.keep_pull : 0.0f;
  if (priors.zones && priors.skin) {
    lp.skin_count = uint32_t(std::min<size_t>(priors.skin->chroma.size(), SKIN_REFS_MAX));
    lp.skin_tolerance = priors.skin_tolerance;
    lp.skin_lum_floor = priors.skin->lum_floor;
    for (uint32_t k = 0; k < lp.skin_count; ++k)
      lp.skin_chroma[2 * k] = priors.skin->chroma[k][0],
                         lp.skin_chroma[2 * k + 1] = priors.skin->chroma[k][1];
  }
  return lp;
}

double RayBatch::render(uint32_t loss_kind, bool forward_only, float min_transmittance,
                        const RayPriors& priors) {
  if (written_rays_ == 0) return 0.0;
  cl::Runtime& rt = model_.runtime();
  const LossParams lp = loss_params(loss_kind, forward_only, min_transmittance, priors);
  render_k_
      .args(lp, sub_offsets_, on_device_ ? counts_dev_ : sub_counts_, ray_info_, sigma_, rgb_, dsigma_, drgb_,
            ray_loss_, ray_color_, pos_, priors.zones ? *priors.zones : no_zones_)
      .launch(rt, written_rays_, ray_group(rt));
  if (forward_only) return 0.0;
  std::vector<float> losses = ray_loss_.read(rt, written_rays_);
  double sum = 0.0;  // fixed order: deterministic
  for (float l : losses) sum += l;
  return sum;
}

std::vector<float> RayBatch::far_shares(const NearRegion& near, float min_transmittance) {
  if (written_rays_ == 0) return {};
  cl::Runtime& rt = model_.runtime();
  LossParams lp = loss_params(LOSS_L2_LINEAR, true, min_transmittance, {});
  lp.near = near;
  far_k_.args(lp, sub_offsets_, on_device_ ? counts_dev_ : sub_counts_, sigma_, pos_, ray_share_)
      .launch(rt, written_rays_, ray_group(rt));
  return ray_share_.read(rt, written_rays_);
}

std::vector<float> RayBatch::colors() const {
  return ray_color_.read(model_.runtime(), size_t(written_rays_) * 4);
}

}  // namespace lorgnette::nerf
