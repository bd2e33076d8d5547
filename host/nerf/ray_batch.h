// The sampling and volume-rendering stages of one batch of rays around the field: count samples
// per ray (kernel), turn counts into offsets (prefix sum, deterministic), write the compacted
// samples of a prefix of rays that fits the field's batch (kernel), then composite them into
// colours and, for training, the loss and its gradient per sample (kernel). Two ways through: the
// host way (count / fit / write / render: counts and losses come back to the host, for tests, the
// room model and evaluation) and the device way (sample_on_device / render_on_device: offsets, fit
// and loss sum stay on the device, and the only transfer is one read of a 16-byte batch record).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "host/cl/kernel.h"
#include "host/nerf/model.h"
#include "host/nerf/subject_volume.h"
#include "host/nerf/views.h"
#include "kernels/train/train_types.h"

namespace lorgnette::nerf {

// SampleParams for `model` (AABB, step, occupancy resolution, per-ray cap, stride); the caller
// fills the ray-selection fields (mode, n_rays, camera/first_pixel or seed/iteration).
SampleParams sample_params_for(const NerfModel& model, const DeviceViews& views);

// The opacity prior of a training render (kernels/train/render.h): its weight (0 = off), and the
// room-explained clearing relative to it with the RMS sRGB difference at which that gate closes, and
// its zones (render_ray_opacity_prior_zones: the keep, lean and solid cells' bitfields, one after
// the other, at zone_res^3 over the model's box; null = none) with the lean cells' least gate.
struct RayPriors {
  float weight = 0.0f;
  float room_clear = 0.0f;
  float room_clear_tolerance = 0.0f;
  const cl::Buffer<uint32_t>* zones = nullptr;
  uint32_t zone_res = 0;
  float lean_gate = 0.0f;
  float solid_pull = 0.0f;        // the solid cells' pull towards an opaque ray (the zones' third bitfield)
  float subject_explains = 0.0f;  // the gate's margin for what the subject explains (render_ray_clear_gate)
  // The skin's colours for the keep cells' clearing (render_ray_skin_like; null = the keep cells'
  // binary prior alone) and the chromaticity distance within which a pixel matches one.
  const SkinChroma* skin = nullptr;
  float skin_tolerance = 0.0f;
  float keep_pull = 0.0f;  // the pull towards an opaque ray of the keep cells within the reach cells
};

class RayBatch {
 public:
  RayBatch(NerfModel& model, uint32_t max_rays);

  uint32_t max_rays() const { return max_rays_; }
  // Sample counts of rays [0, p.n_rays) (p.n_rays <= max_rays()); kept on the host.
  const std::vector<uint32_t>& count(const SampleParams& p, const DeviceViews& views);
  // Largest end such that rays [begin, end) have at most `budget` samples in total (>= begin + 1
  // unless begin == n_rays; a single ray never exceeds the budget because max_samples <= budget).
  uint32_t fit(uint32_t begin, uint32_t budget) const;
  // Writes the samples of rays [begin, end) into positions()/directions(); returns the sample count.
  uint32_t write(SampleParams p, const DeviceViews& views, uint32_t begin, uint32_t end);
  // Composites the written rays (after the field filled sigma()/rgb()). Training: also the loss
  // gradient into dsigma()/drgb() with grad_scale = 1 / (3 * rays); returns the summed squared error.
  // priors.weight > 0 adds the opacity prior's gradient (kernels/train/render.h).
  double render(uint32_t loss_kind, bool forward_only, float min_transmittance = 1e-4f,
                const RayPriors& priors = {});
  // Colour + opacity (4 floats per ray) of the last render().
  std::vector<float> colors() const;
  // Per written ray, after the field filled sigma(): the share of its colour that its samples outside
  // `near` (positions normalised to the model's box) and the background give
  // (kernels/train/render.h render_ray_share_beyond).
  std::vector<float> far_shares(const NearRegion& near, float min_transmittance = 1e-4f);

  // The device way. Counts rays [0, p.n_rays), scans the counts into offsets and fits the leading
  // rays into `budget` = the field's batch (kernel sample_offsets), writes their samples, then reads
  // the batch record back: the step's only blocking transfer. It also brings the summed loss of the
  // previous render_on_device() (the queue is in order), so the caller can read that loss without
  // a transfer of its own.
  struct DeviceBatch {
    uint32_t rays = 0, samples = 0;  // the rays written and their samples
    uint64_t counted = 0;            // samples of all p.n_rays rays
    float previous_loss_sum = 0.0f;  // BATCH_INFO_LOSS at the time of the read
  };
  DeviceBatch sample_on_device(SampleParams p, const DeviceViews& views);
  // render() for the rays of the last sample_on_device(), with the loss summed on the device into
  // the batch record (no transfer). The sum arrives with the next sample_on_device() or loss_sum().
  void render_on_device(uint32_t loss_kind, float min_transmittance = 1e-4f, const RayPriors& priors = {});
  // Blocking read of the summed loss of the last render_on_device().
  float loss_sum() const;

  cl::Buffer<float>& positions() { return pos_; }
  cl::Buffer<float>& directions() { return dir_; }
  cl::Buffer<float>& sigma() { return sigma_; }
  cl::Buffer<float>& rgb() { return rgb_; }
  cl::Buffer<float>& dsigma() { return dsigma_; }
  cl::Buffer<float>& drgb() { return drgb_; }
  // RAY_INFO_FLOATS per written ray (target rgb, background rgb, pixel, image as float bits, far share).
  const cl::Buffer<float>& ray_info() const { return ray_info_; }
  // Writable, for a background model that replaces the rays' background colours (background_field.h).
  cl::Buffer<float>& ray_info_mut() { return ray_info_; }
  uint32_t written_samples() const { return written_samples_; }

 private:
  LossParams loss_params(uint32_t loss_kind, bool forward_only, float min_transmittance,
                         const RayPriors& priors) const;

  NerfModel& model_;
  uint32_t max_rays_, stride_;
  cl::Kernel count_k_, offsets_k_, write_k_, render_k_, loss_sum_k_, far_k_;
  std::vector<uint32_t> counts_;
  cl::Buffer<uint32_t> counts_dev_, sub_offsets_, sub_counts_, batch_info_;
  cl::Buffer<float> ray_info_, ray_loss_, ray_color_, ray_share_;
  cl::Buffer<float> pos_, dir_, sigma_, rgb_, dsigma_, drgb_;
  cl::Buffer<uint32_t> no_zones_;  // bound as the zones when RayPriors has none
  uint32_t written_rays_ = 0, written_samples_ = 0;
  bool on_device_ = false;  // the last write was sample_on_device (counts in counts_dev_)
};

}  // namespace lorgnette::nerf
