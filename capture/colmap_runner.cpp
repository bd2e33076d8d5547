// The COLMAP stages of `lorgnette capture` (see colmap_runner.h): command lines chosen for a 2-core
// CPU, progress parsed from COLMAP's log, and failures turned into messages that say what to do.
#include "capture/colmap_runner.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <fstream>
#include <regex>
#include <stdexcept>

#include "capture/colmap_model.h"
#include "capture/subprocess.h"
#include "host/util/progress.h"

namespace fs = std::filesystem;

namespace lorgnette::capture {
namespace {

// Last "[a/b]" counter (features, matching) or mapper registration count in the log's tail.
double log_progress(const fs::path& log, bool mapper) {
  std::ifstream f(log, std::ios::binary);
  if (!f) return 0;
  f.seekg(0, std::ios::end);
  std::streamoff size = f.tellg();
  f.seekg(std::max<std::streamoff>(0, size - 4096));
  std::string tail((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  static const std::regex counter(R"(\[(\d+)/(\d+))"), registered(R"(Registering image #\d+ \((\d+)\))");
  const std::regex& re = mapper ? registered : counter;
  double value = 0;
  for (auto it = std::sregex_iterator(tail.begin(), tail.end(), re); it != std::sregex_iterator(); ++it)
    value = std::stod((*it)[1].str());
  return value;
}

void run_stage(const fs::path& exe, const std::string& stage, const std::vector<std::string>& args,
               const fs::path& log, double total, ColmapResult& result) {
  std::error_code ec;
  fs::remove(log, ec);
  Progress progress(fmt::format("colmap {}", stage), total, "img");
  bool mapper = stage == "mapper";
  double done = 0;
  ProcessResult r = run_process(exe, args, log, {"QT_QPA_PLATFORM=offscreen"}, [&] {
    // The counter can scroll out of the log tail: never go backwards.
    done = std::max(done, log_progress(log, mapper));
    progress.update(done);
  });
  progress.finish();
  result.seconds.push_back({stage, r.seconds});
  if (r.interrupted) throw std::runtime_error(fmt::format("interrupted during colmap {}", stage));
  if (r.exit_code != 0) {
    std::string hint;
    std::string tail = file_tail(log, 15);
    if (tail.find("No good initial image pair") != std::string::npos)
      hint =
          "\nThe frames have too few matches: take more overlapping photos of a textured scene, or "
          "try --matcher exhaustive.";
    throw std::runtime_error(
        fmt::format("colmap {} failed (exit status {}); its log is '{}'. Last lines:\n{}{}", stage,
                    r.exit_code, log.string(), tail, hint));
  }
}

std::vector<std::string> common_sift(const ColmapSettings& s) {
  return {"--SiftMatching.use_gpu", "0", "--SiftMatching.num_threads", std::to_string(s.threads)};
}

}  // namespace

fs::path find_colmap(const ColmapSettings& settings) {
  std::string name = settings.executable.empty() ? "colmap" : settings.executable;
  fs::path exe = find_executable(name);
  if (exe.empty())
    throw std::runtime_error(fmt::format(
        "COLMAP ('{}') was not found on PATH: install Debian's package with `sudo apt-get install "
        "colmap`, or give a folder that already holds a COLMAP model (sparse/0)",
        name));
  return exe;
}

ColmapResult run_colmap(const fs::path& image_dir, const fs::path& workspace, size_t image_count,
                        const ColmapSettings& s) {
  if (s.matcher != "sequential" && s.matcher != "exhaustive")
    throw std::runtime_error(fmt::format("unknown matcher '{}': use sequential or exhaustive", s.matcher));
  fs::path exe = find_colmap(s);
  fs::create_directories(workspace / "sparse");
  fs::path db = workspace / "database.db";
  std::error_code ec;
  fs::remove(db, ec);  // a stale database would mix old frames in
  for (const auto& e : fs::directory_iterator(workspace / "sparse")) fs::remove_all(e.path(), ec);
  ColmapResult result;
  double n = static_cast<double>(image_count);

  run_stage(
      exe, "features",
      {"feature_extractor", "--database_path", db.string(), "--image_path", image_dir.string(),
       "--ImageReader.camera_model", "OPENCV", "--ImageReader.single_camera", "1", "--SiftExtraction.use_gpu",
       "0", "--SiftExtraction.num_threads", std::to_string(s.threads), "--SiftExtraction.max_num_features",
       std::to_string(s.max_features), "--SiftExtraction.max_image_size", std::to_string(s.max_image_size)},
      workspace / "features.log", n, result);

  std::vector<std::string> match = {s.matcher + "_matcher", "--database_path", db.string()};
  for (auto& a : common_sift(s)) match.push_back(a);
  if (s.matcher == "sequential")
    match.insert(match.end(), {"--SequentialMatching.overlap", std::to_string(s.sequential_overlap),
                               "--SequentialMatching.quadratic_overlap", "1"});
  run_stage(exe, "matching", match, workspace / "matching.log", n, result);

  run_stage(exe, "mapper",
            {"mapper", "--database_path", db.string(), "--image_path", image_dir.string(), "--output_path",
             (workspace / "sparse").string(), "--Mapper.num_threads", std::to_string(s.threads)},
            workspace / "mapper.log", n, result);

  for (const auto& e : fs::directory_iterator(workspace / "sparse")) {
    if (!e.is_directory() || !is_colmap_model_dir(e.path())) continue;
    ++result.models;
    size_t count = read_colmap_model(e.path()).images.size();
    if (count > result.registered) result.registered = count, result.model_dir = e.path();
  }
  if (result.models == 0)
    throw std::runtime_error(fmt::format(
        "COLMAP could not reconstruct the scene: too few matches between the frames (log: '{}'). "
        "Take more overlapping photos (move slowly around the head), with light and texture, or try "
        "--matcher exhaustive",
        (workspace / "mapper.log").string()));
  if (result.models > 1)
    result.warnings.push_back(fmt::format(
        "COLMAP made {} disconnected models; kept the largest ({} of {} frames, '{}'): the others "
        "did not overlap enough with it",
        result.models, result.registered, image_count, result.model_dir.string()));
  if (result.registered * 2 < image_count)
    result.warnings.push_back(fmt::format("only {} of {} frames got a pose", result.registered, image_count));
  return result;
}

}  // namespace lorgnette::capture
