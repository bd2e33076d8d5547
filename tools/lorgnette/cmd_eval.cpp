// `lorgnette eval MODEL DATA`: PSNR and SSIM of a trained model over held-out views (test split for
// NeRF-synthetic, every 8th frame of a transforms.json), optional prediction|truth|error images,
// and `--json` for scripts.
#include <filesystem>
#include <iostream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "host/dataset/dataset.h"
#include "host/render/evaluate.h"
#include "tools/lorgnette/command.h"

namespace lorgnette::cli {
namespace {

struct EvalArgs {
  std::string model, data, split, output;
  uint32_t max_views = 0, downscale = 1, max_side = 0;
  bool json = false, black = false, force = false;
};

// The comparison images evaluate() writes are <index>_pred_truth_error.png: refuse a directory that
// already holds some unless --force (they would be overwritten, or mixed with this run's).
void check_output_dir(const EvalArgs& a) {
  std::error_code ec;
  if (a.output.empty() || a.force || !std::filesystem::is_directory(a.output, ec)) return;
  const std::string suffix = "_pred_truth_error.png";
  for (const auto& e : std::filesystem::directory_iterator(a.output, ec)) {
    const std::string name = e.path().filename().string();
    if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
      throw std::runtime_error(fmt::format("'{}' already holds evaluation images ({} ...): pass --force to "
                                           "overwrite them or choose another -o", a.output, name));
  }
}

void run_eval(const EvalArgs& a, GlobalOptions& global) {
  check_output_dir(a);
  cl::Runtime rt(global.runtime());
  nerf::NerfModel model = nerf::NerfModel::load(rt, a.model);
  dataset::LoadOptions lo;
  lo.downscale = int(a.downscale);
  lo.max_side = int(a.max_side);
  dataset::Split split;
  if (a.split.empty()) {
    dataset::LoadOptions probe = lo;
    probe.load_images = false;
    split = dataset::load_dataset(a.data, probe).default_eval_split();
  } else {
    split = dataset::split_from_string(a.split);
  }
  lo.splits = {split};
  dataset::Dataset ds = dataset::load_dataset(a.data, lo);
  std::vector<nerf::View> views;
  for (const dataset::Frame* f : ds.require_split(split)) views.push_back({f->camera, &f->image});
  render::EvalOptions eo;
  eo.max_views = a.max_views;
  eo.output_dir = a.output;
  if (a.black) eo.background = {0.0f, 0.0f, 0.0f};
  render::EvalResult r = render::evaluate(model, views, eo);
  if (a.json) {
    nlohmann::json out = {{"psnr", r.psnr}, {"ssim", r.ssim}, {"views", r.views},
                          {"split", dataset::to_string(split)}, {"train_seconds", model.metadata.train_seconds},
                          {"steps", model.metadata.steps}, {"eval_seconds", r.seconds},
                          {"view_psnr", r.view_psnr}, {"view_ssim", r.view_ssim}, {"model", a.model}};
    std::cout << out.dump() << "\n";
  } else {
    std::cout << fmt::format("{} views ({}): PSNR {:.2f} dB, SSIM {:.4f} (model: {} steps, {:.0f} s training)\n",
                             r.views, dataset::to_string(split), r.psnr, r.ssim, model.metadata.steps,
                             model.metadata.train_seconds);
  }
  if (!a.output.empty()) spdlog::info("prediction | truth | error images in '{}'", a.output);
}

void add_eval(CLI::App& app, GlobalOptions& global) {
  auto* cmd = app.add_subcommand("eval", "PSNR / SSIM of a trained model on held-out views");
  auto a = std::make_shared<EvalArgs>();
  cmd->add_option("MODEL", a->model, "model file (.lnerf)")->required();
  cmd->add_option("DATA", a->data, "dataset directory or json file")->required();
  cmd->add_option("--split", a->split, "test | val | holdout (default: test, or holdout for transforms.json)");
  cmd->add_option("-o,--output", a->output, "directory for prediction|truth|error images");
  cmd->add_option("--max-views", a->max_views, "evaluate at most this many views, evenly spaced");
  cmd->add_option("--downscale", a->downscale, "integer image downscale factor (as in training)");
  cmd->add_option("--max-side", a->max_side, "shrink images so the longer side is at most this");
  cmd->add_flag("--black", a->black, "black background instead of white for RGBA truth");
  cmd->add_flag("--json", a->json, "print one JSON object on stdout");
  cmd->add_flag("--force", a->force, "overwrite evaluation images already in the -o directory");
  cmd->callback([a, &global] { run_eval(*a, global); });
}

}  // namespace
LGN_REGISTER_COMMAND(21, add_eval);
}  // namespace lorgnette::cli
