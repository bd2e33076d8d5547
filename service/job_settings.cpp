// job.json (job_settings.h).
#include "service/job_settings.h"

#include <fmt/format.h>

#include <fstream>
#include <stdexcept>

#include "host/util/bounds.h"
#include "host/util/image_io.h"

namespace lorgnette::service {

nlohmann::json JobSettings::to_json() const {
  return {{"catalogue", catalogue},
          {"capture_fps", capture_fps},
          {"capture_max_frames", capture_max_frames},
          {"capture_max_side", capture_max_side},
          {"train_steps", train_steps},
          {"train_batch_log2", train_batch_log2},
          {"train_seed", train_seed},
          {"train_max_side", train_max_side},
          {"train_snapshot_seconds", train_snapshot_seconds},
          {"fit_views", fit_views},
          {"fit_resolution", fit_resolution},
          {"tryon_views", tryon_views},
          {"tryon_size", tryon_size}};
}

JobSettings JobSettings::from_json(const nlohmann::json& j) {
  JobSettings s;
  try {
    s.catalogue = j.value("catalogue", s.catalogue);
    s.capture_fps = j.value("capture_fps", s.capture_fps);
    s.capture_max_frames = j.value("capture_max_frames", s.capture_max_frames);
    s.capture_max_side = j.value("capture_max_side", s.capture_max_side);
    s.train_steps = j.value("train_steps", s.train_steps);
    s.train_batch_log2 = j.value("train_batch_log2", s.train_batch_log2);
    s.train_seed = j.value("train_seed", s.train_seed);
    s.train_max_side = j.value("train_max_side", s.train_max_side);
    s.train_snapshot_seconds = j.value("train_snapshot_seconds", s.train_snapshot_seconds);
    s.fit_views = j.value("fit_views", s.fit_views);
    s.fit_resolution = j.value("fit_resolution", s.fit_resolution);
    s.tryon_views = j.value("tryon_views", s.tryon_views);
    s.tryon_size = j.value("tryon_size", s.tryon_size);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("job settings: a field has the wrong type: ") + e.what());
  }
  s.validate();
  return s;
}

// The stages' own ranges (host/util/bounds.h), so a job the server accepts is one the stages run;
// the message names the serve flag that sets the field.
void JobSettings::validate() const {
  namespace b = bounds;
  try {
    check_bound(b::kJobCaptureFps, capture_fps);
    check_bound_or_zero(b::kJobCaptureMaxFrames, capture_max_frames);
    check_bound_or_zero(b::kJobCaptureSide, capture_max_side);
    check_bound_or_zero(b::kJobTrainSteps, double(train_steps));
    check_bound_or_zero(b::kJobBatchLog2, train_batch_log2);
    check_bound_or_zero(b::kJobTrainSide, train_max_side);
    check_bound_or_zero(b::kJobTrainSnapshot, train_snapshot_seconds);
    check_bound(b::kJobFitViews, fit_views);
    check_bound(b::kJobFitResolution, fit_resolution);
    check_bound(b::kJobTryonViews, tryon_views);
    check_bound(b::kJobTryonSize, tryon_size);
  } catch (const OutOfRange& e) {
    throw OutOfRange(fmt::format("job settings: {}", e.what()));
  }
}

void write_job_settings(const std::filesystem::path& path, const JobSettings& s) {
  write_text_file_atomic(path.string(), s.to_json().dump(2) + "\n");
}

JobSettings read_job_settings(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("cannot read the job settings '{}'", path.string()));
  nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.is_object())
    throw std::runtime_error(fmt::format("'{}' is not a JSON object of job settings", path.string()));
  return JobSettings::from_json(j);
}

}  // namespace lorgnette::service
