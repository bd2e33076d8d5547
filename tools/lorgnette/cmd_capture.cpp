// `lorgnette capture INPUT -o DATASET`: a phone video, a folder of photos, or a folder holding a
// COLMAP model -> a posed dataset (transforms.json + images/, COLMAP workspace in colmap/).
#include <spdlog/spdlog.h>

#include <iostream>

#include "capture/capture.h"
#include "tools/lorgnette/command.h"

namespace lorgnette::cli {
namespace {

void print_summary(const capture::CaptureReport& r) {
  std::cerr << fmt::format(
      "{} frames read, {} kept, {} posed ({} model{}), mean reprojection error {:.2f} px\n",
      r.candidate_frames, r.kept_frames, r.registered, r.models, r.models == 1 ? "" : "s",
      r.mean_reprojection_error);
  for (const auto& d : r.dropped) std::cerr << fmt::format("  dropped {}: {}\n", d.name, d.reason);
  for (const auto& s : r.seconds) std::cerr << fmt::format("  {:<9} {:8.1f} s\n", s.stage, s.seconds);
  std::cerr << fmt::format("subject box from {}: {}\n", r.aabb_from, r.aabb_note);
  if (r.coverage)
    std::cerr << fmt::format("covered {}{}\n", r.coverage->summary(),
                             r.coverage_advice.empty() ? " (ear to ear)" : "\n  " + r.coverage_advice);
  if (r.card.value("searched", false)) std::cerr << r.card.value("message", "") << "\n";
  std::cerr << fmt::format("wrote {}\n", r.transforms_path);
}

void add_capture(CLI::App& app, GlobalOptions& global) {
  auto* cmd = app.add_subcommand(
      "capture", "make a posed dataset (transforms.json) from a video, photos, or a COLMAP model");
  auto opt = std::make_shared<capture::CaptureOptions>();
  auto json = std::make_shared<bool>(false);
  auto no_blur = std::make_shared<bool>(false), no_blink = std::make_shared<bool>(false);
  auto no_head_box = std::make_shared<bool>(false), no_card = std::make_shared<bool>(false);
  auto card_only = std::make_shared<bool>(false);
  cmd->add_option("INPUT", opt->input,
                  "video file, folder of images, or folder with a COLMAP model (sparse/0)")
      ->required();
  cmd->add_option("-o,--output", opt->output,
                  "dataset folder to write (new, empty, or an earlier capture with --force)");
  cmd->add_option("--fps", opt->frames.fps, "frames per second of video to sample")->capture_default_str();
  cmd->add_option("--max-frames", opt->frames.max_frames, "at most this many frames, evenly spread (0: all)")
      ->capture_default_str();
  cmd->add_option("--matcher", opt->colmap.matcher,
                  "COLMAP matching: sequential (ordered frames) or exhaustive")
      ->capture_default_str()
      ->check(CLI::IsMember({"sequential", "exhaustive"}));
  cmd->add_option("--size", opt->frames.max_side, "longer side of the frames in pixels (0: keep)")
      ->capture_default_str();
  cmd->add_option("--max-features", opt->colmap.max_features, "SIFT features per frame")
      ->capture_default_str();
  cmd->add_option("--colmap", opt->colmap.executable, "COLMAP executable (default: colmap on PATH)");
  cmd->add_flag("--no-blur-filter", *no_blur, "keep blurred frames");
  cmd->add_flag("--no-blink-filter", *no_blink, "keep frames with closed eyes (and skip face detection)");
  cmd->add_flag("--no-head-box", *no_head_box,
                "box the sparse points instead of the head found by its landmarks");
  cmd->add_flag("--no-card", *no_card, "do not look for a held ID-1 card (the dataset's millimetres)");
  cmd->add_flag("--card-only", *card_only,
                "INPUT is a posed dataset (transforms.json and images, e.g. a synth output): only "
                "measure the held card and write INPUT/scale.json and INPUT/ignore_regions.json (the "
                "card and its fingers, left out of training) (no -o)");
  cmd->add_flag("--force", opt->force, "replace an earlier capture in the output folder");
  cmd->add_flag("--json", *json, "print the capture report as one JSON object on stdout");
  cmd->callback([opt, json, no_blur, no_blink, no_head_box, no_card, card_only] {
    if (*card_only) {
      if (!opt->output.empty() || *no_card)
        throw std::runtime_error("--card-only writes INPUT/scale.json: give no -o and no --no-card");
      capture::CaptureReport report;
      capture::measure_card_in_capture(opt->input, report);
      if (*json)
        std::cout << report.card.dump(2) << "\n";
      else
        std::cerr << report.card.value("message", "") << "\n";
      return;
    }
    opt->card = !*no_card;
    opt->blur_filter = !*no_blur;
    opt->head_box = !*no_head_box;
    opt->blink_filter = !*no_blink;
    capture::CaptureReport report = capture::run_capture(*opt);
    if (*json)
      std::cout << report.to_json().dump(2) << "\n";
    else
      print_summary(report);
  });
  (void)global;
}

}  // namespace
LGN_REGISTER_COMMAND(30, add_capture);
}  // namespace lorgnette::cli
