// Camera poses with COLMAP (Debian's `colmap`, CPU only): feature extraction with one shared OPENCV
// camera, sequential or exhaustive matching, incremental mapping, each as a subprocess whose output
// is kept in the workspace (features.log, matching.log, mapper.log). Failures are explained: COLMAP
// missing (names the Debian package), a stage failing (its log tail), too few matches (no model),
// several disconnected models (the largest is kept and a warning says so).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace lorgnette::capture {

struct ColmapSettings {
  std::string executable;              // empty: `colmap` on PATH
  std::string matcher = "sequential";  // "sequential" (ordered frames) or "exhaustive"
  int max_features = 2048;             // SIFT features per image: bounds matching time on 2 cores
  int max_image_size = 1024;           // SIFT works on images downscaled to this longer side
  int sequential_overlap = 10;         // each frame is matched with this many following frames
  int threads = -1;                    // -1: all cores
};

struct StageSeconds {
  std::string stage;
  double seconds = 0;
};

struct ColmapResult {
  std::filesystem::path model_dir;    // the chosen sparse model (largest)
  size_t models = 0;                  // models COLMAP produced
  size_t registered = 0;              // images in the chosen model
  std::vector<StageSeconds> seconds;  // features, matching, mapper
  std::vector<std::string> warnings;
};

// Resolves the COLMAP executable or throws naming the Debian package.
std::filesystem::path find_colmap(const ColmapSettings& settings);

// Runs the three stages on `image_dir` with `workspace` (created) holding database.db, sparse/ and
// the logs. `image_count` is for progress and the registration report. Throws with a clear message.
ColmapResult run_colmap(const std::filesystem::path& image_dir, const std::filesystem::path& workspace,
                        size_t image_count, const ColmapSettings& settings);

}  // namespace lorgnette::capture
