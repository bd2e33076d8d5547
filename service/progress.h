// A job's progress as its worker reports it: one small JSON file in the capture's folder, replaced
// atomically (temporary file + rename) so the server never reads half a file. The worker is its only
// writer; the server reads it to answer status requests and to learn why a job failed.
#pragma once
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace lorgnette::service {

struct Progress {
  std::string state = "running";  // running | failed | finished
  std::string stage;              // capture | train | fit ("" before the first stage)
  double percent = 0.0;           // of the whole job, 0..100
  double eta_seconds = -1.0;      // of the whole job; < 0: not known yet
  std::string message;            // what the worker is doing, or (failed) the product's own error
  nlohmann::json artifacts = nlohmann::json::object();  // paths relative to the capture folder
  // Seconds of each stage this worker run completed (stage name -> seconds, the worker's clock):
  // how executors that do not watch the worker (Slurm) measure stages for /metrics.
  nlohmann::json stage_seconds = nlohmann::json::object();
  int64_t updated_unix = 0;  // set by write_progress

  nlohmann::json to_json() const;
  static Progress from_json(const nlohmann::json& j);
};

// Writes `p` (with updated_unix = now) through a temporary file and rename.
void write_progress(const std::filesystem::path& path, Progress p);

// The progress in `path`; nothing when the file is absent or unreadable (a worker that has not
// started yet, or a file from another version), never an exception.
std::optional<Progress> read_progress(const std::filesystem::path& path);

}  // namespace lorgnette::service
