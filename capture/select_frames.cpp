// The frame-selection stage of a capture: blur filter, then blink filter on the sharp frames, with
// progress, and every dropped frame recorded with its reason.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <memory>

#include "capture/capture.h"
#include "capture/eye_openness.h"
#include "host/util/interrupt.h"
#include "host/util/progress.h"

namespace lorgnette::capture {
namespace {

// Applies a decision over the frames `idx` (positions into `frames`), recording what was dropped.
std::vector<size_t> apply(const FilterDecision& d, const std::vector<size_t>& idx, const FrameSet& frames,
                          CaptureReport& report) {
  std::vector<size_t> kept;
  for (size_t k = 0; k < idx.size(); ++k) {
    if (d.keep[k])
      kept.push_back(idx[k]);
    else
      report.dropped.push_back({frames.names[idx[k]], d.reasons[k]});
  }
  report.warnings.insert(report.warnings.end(), d.warnings.begin(), d.warnings.end());
  return kept;
}

}  // namespace

std::vector<size_t> select_frames(const FrameSet& frames, const CaptureOptions& opt, CaptureReport& report) {
  std::vector<size_t> idx;
  for (size_t i = 0; i < frames.images.size(); ++i) idx.push_back(i);
  if (opt.blur_filter && idx.size() >= 3) {
    std::vector<double> sharpness;
    for (size_t i : idx) sharpness.push_back(laplacian_variance(frames.images[i]));
    idx = apply(blur_filter(sharpness, opt.blur), idx, frames, report);
  }
  if (opt.blink_filter && !idx.empty()) {
    std::unique_ptr<EyeOpenness> eyes;
    try {
      eyes = std::make_unique<EyeOpenness>(opt.landmark_model);
    } catch (const std::exception& e) {
      report.warnings.push_back(fmt::format("blink filter skipped: {}", e.what()));
    }
    if (eyes) {
      std::vector<std::optional<double>> ear;
      Progress progress("eyes", static_cast<double>(idx.size()), "img");
      for (size_t k = 0; k < idx.size() && !interrupted(); ++k) {
        ear.push_back(eyes->measure(frames.images[idx[k]]));
        report.faces_found += ear.back().has_value();
        progress.update(k + 1.0, fmt::format("{} faces", report.faces_found));
      }
      progress.finish(fmt::format("{} faces in {} frames", report.faces_found, idx.size()));
      if (interrupted()) throw std::runtime_error("interrupted while checking eyes");
      idx = apply(blink_filter(ear, opt.blink), idx, frames, report);
    }
  }
  return idx;
}

}  // namespace lorgnette::capture
