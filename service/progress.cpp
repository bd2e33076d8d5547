// Reading and writing progress.json (progress.h).
#include "service/progress.h"

#include <chrono>
#include <fstream>

#include "host/util/image_io.h"

namespace lorgnette::service {

nlohmann::json Progress::to_json() const {
  return {{"state", state},
          {"stage", stage},
          {"percent", percent},
          {"message", message},
          {"eta_seconds", eta_seconds},
          {"artifacts", artifacts},
          {"stage_seconds", stage_seconds},
          {"updated_unix", updated_unix}};
}

Progress Progress::from_json(const nlohmann::json& j) {
  Progress p;
  p.state = j.at("state").get<std::string>();
  p.stage = j.value("stage", "");
  p.percent = j.value("percent", 0.0);
  p.message = j.value("message", "");
  p.eta_seconds = j.value("eta_seconds", -1.0);
  p.artifacts = j.value("artifacts", nlohmann::json::object());
  p.stage_seconds = j.value("stage_seconds", nlohmann::json::object());
  p.updated_unix = j.value("updated_unix", int64_t(0));
  return p;
}

void write_progress(const std::filesystem::path& path, Progress p) {
  p.updated_unix =
      std::chrono::duration_cast<std::chrono::seconds>(std::chrono::system_clock::now().time_since_epoch())
          .count();
  write_text_file_atomic(path.string(), p.to_json().dump(2) + "\n");
}

std::optional<Progress> read_progress(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  try {
    return Progress::from_json(nlohmann::json::parse(in));
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

}  // namespace lorgnette::service
