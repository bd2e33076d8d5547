// The settings of one job, chosen by the shop (the server's flags) and written into the capture's
// folder as job.json when the capture is created, so a worker started anywhere (another slot, a
// requeued run) computes exactly what the server asked for. Every field has the product's default.
#pragma once
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace lorgnette::service {

struct JobSettings {
  std::string catalogue;  // folder of the shop's frames (viewer/catalogue.h); "" = no fits
  // Capture: video sampling and frame size (capture::FrameOptions).
  double capture_fps = 2.0;
  int capture_max_frames = 150;
  int capture_max_side = 768;
  // Training budget (the shop-wide budget): steps, 0 = the size-based default (train_budget.h);
  // batch as log2 of the samples per step, 0 = the device's default.
  uint64_t train_steps = 0;
  uint32_t train_batch_log2 = 0;
  uint32_t train_seed = 1337;
  int train_max_side = 0;  // shrink training images to this longer side (0: keep)
  // Seconds between training checkpoints (host/nerf/checkpoint.h): at most this much training is
  // trained again when a worker dies. 0: only at the end.
  double train_snapshot_seconds = 60.0;
  // Fit (fit::FitSettings): rendered views and their size.
  int fit_views = 12;
  int fit_resolution = 384;
  // Try-on views per fitted frame (product_calls.h render_tryon_views): an orbit of this many square
  // images of this side, rendered once and served as files.
  int tryon_views = 12;
  int tryon_size = 512;

  nlohmann::json to_json() const;
  // Throws naming the field that is missing, of the wrong type or out of range.
  static JobSettings from_json(const nlohmann::json& j);
  void validate() const;
};

void write_job_settings(const std::filesystem::path& path, const JobSettings& s);  // atomic
JobSettings read_job_settings(const std::filesystem::path& path);                  // throws with the path

}  // namespace lorgnette::service
