// capture_bench: runs `lorgnette capture` on the 50 fox photos and the in2n-face head frames,
// recording the seconds of every stage and the pose accuracy against each capture's provided
// transforms.json. Writes capture_stages.csv, capture_accuracy.csv and capture_stages.png to --out.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "capture/capture.h"
#include "eval/pose_compare.h"
#include "host/util/chart.h"

namespace fs = std::filesystem;
using namespace lorgnette;
using namespace lorgnette::capture;

namespace {

struct Case {
  std::string name, images, reference;
  int size;
  bool blink;
};

struct Result {
  Case c;
  CaptureReport report;
  PoseAccuracy acc;
};

Result run_case(const Case& c, const fs::path& out, const std::string& matcher, int max_frames) {
  CaptureOptions opt;
  opt.input = c.images;
  opt.output = (out / c.name).string();
  fs::remove_all(opt.output);
  opt.frames.max_side = c.size;
  opt.frames.max_frames = max_frames;
  opt.blink_filter = c.blink;
  opt.colmap.matcher = matcher;
  spdlog::info("capture {} ({}, size {}, {} matcher)", c.name, c.images, c.size, matcher);
  Result r{c, run_capture(opt), {}};
  r.acc = compare_poses(opt.output, c.reference);
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"capture stage times and pose accuracy"};
  std::string out = "capture-bench", matcher = "sequential", only;
  int max_frames = 0;
  app.add_option("--out", out, "output folder (datasets, CSV, chart)");
  app.add_option("--matcher", matcher, "sequential or exhaustive");
  app.add_option("--max-frames", max_frames, "limit frames per capture (0: all)");
  app.add_option("--only", only, "run one case: fox or in2n-face");
  std::string compare, reference;
  app.add_option("--compare", compare, "only compare this dataset's poses with --reference");
  app.add_option("--reference", reference, "reference transforms.json for --compare");
  CLI11_PARSE(app, argc, argv);
  if (!compare.empty()) {
    PoseAccuracy a = compare_poses(compare, reference);
    std::cout << fmt::format(
        "{} frames: rotation error mean {:.3f} max {:.3f} deg, centre error mean "
        "{:.2f}% max {:.2f}%, mean camera-frame residual ({:.2f}, {:.2f}, {:.2f}) deg\n",
        a.matched, a.rotation_deg_mean, a.rotation_deg_max, 100 * a.centre_rel_mean, 100 * a.centre_rel_max,
        a.residual_camera_deg[0], a.residual_camera_deg[1], a.residual_camera_deg[2]);
    return 0;
  }
  fs::path data = LORGNETTE_DATA_DIR;
  std::vector<Case> cases = {
      {"fox", (data / "nerf/fox/images").string(), (data / "nerf/fox/transforms.json").string(), 640, false},
      {"in2n-face", (data / "heads/in2n-face/images").string(),
       (data / "heads/in2n-face/transforms.json").string(), 512, true}};
  fs::create_directories(out);
  std::vector<std::vector<std::string>> stage_rows, acc_rows;
  std::vector<ChartSeries> series;
  for (const auto& c : cases) {
    if (!only.empty() && only != c.name) continue;
    if (!fs::exists(c.images)) {
      spdlog::warn("skipping {}: {} not found", c.name, c.images);
      continue;
    }
    Result r = run_case(c, out, matcher, max_frames);
    ChartSeries s{c.name, {}, {}, false};
    double total = 0;
    for (size_t i = 0; i < r.report.seconds.size(); ++i) {
      const auto& st = r.report.seconds[i];
      total += st.seconds;
      stage_rows.push_back({c.name, st.stage, fmt::format("{:.3f}", st.seconds)});
      s.x.push_back(static_cast<double>(i));
      s.y.push_back(total);
    }
    series.push_back(s);
    acc_rows.push_back(
        {c.name, std::to_string(r.report.candidate_frames), std::to_string(r.report.kept_frames),
         std::to_string(r.report.registered), std::to_string(r.report.models),
         fmt::format("{:.3f}", r.report.mean_reprojection_error),
         fmt::format("{:.3f}", r.acc.rotation_deg_mean), fmt::format("{:.3f}", r.acc.rotation_deg_max),
         fmt::format("{:.4f}", r.acc.centre_rel_mean), fmt::format("{:.4f}", r.acc.centre_rel_max),
         fmt::format("{:.1f}", total)});
    std::cout << r.report.to_json().dump(2) << "\n";
    std::cout << fmt::format(
        "{}: rotation error mean {:.3f} max {:.3f} deg, centre error mean {:.2f}% max "
        "{:.2f}% of the camera spread ({} frames matched)\n",
        c.name, r.acc.rotation_deg_mean, r.acc.rotation_deg_max, 100 * r.acc.centre_rel_mean,
        100 * r.acc.centre_rel_max, r.acc.matched);
  }
  write_csv((fs::path(out) / "capture_stages.csv").string(), {"capture", "stage", "seconds"}, stage_rows);
  write_csv((fs::path(out) / "capture_accuracy.csv").string(),
            {"capture", "frames", "kept", "registered", "models", "reproj_px", "rot_deg_mean", "rot_deg_max",
             "centre_rel_mean", "centre_rel_max", "total_s"},
            acc_rows);
  if (!series.empty())
    write_chart((fs::path(out) / "capture_stages.png").string(),
                {"capture: cumulative seconds after each stage (frames, select, write, features, "
                 "matching, mapper, convert)",
                 "stage", "seconds"},
                series);
  return 0;
}
