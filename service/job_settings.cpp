// job.json (job_settings.h).
#include "service/job_settings.h"

#include <fmt/format.h>

#include <fstream>
#include <stdexcept>

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

void JobSettings::validate() const {
  auto check = [](bool ok, const char* what) {
    if (!ok) throw std::runtime_error(fmt::format("job settings: {}", what));
  };
  check(capture_fps > 0.0 && capture_fps <= 60.0, "capture_fps must be within (0, 60]");
  check(capture_max_frames >= 0, "capture_max_frames must be >= 0 (0: all)");
  check(capture_max_side >= 0, "capture_max_side must be >= 0 (0: keep)");
  check(train_batch_log2 == 0 || (train_batch_log2 >= 10 && train_batch_log2 <= 22),
        "train_batch_log2 must be 0 (device default) or within 10..22");
  check(train_max_side >= 0, "train_max_side must be >= 0 (0: keep)");
  check(fit_views >= 2 && fit_views <= 200, "fit_views must be within 2..200");
  check(fit_resolution >= 64 && fit_resolution <= 4096, "fit_resolution must be within 64..4096");
  check(tryon_views >= 1 && tryon_views <= 72, "tryon_views must be within 1..72");
  check(tryon_size >= 64 && tryon_size <= 2048, "tryon_size must be within 64..2048");
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
