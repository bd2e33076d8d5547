// `lorgnette fit MODEL --glasses FRAME -o placement.json [--views K] [--debug DIR]`: places the
// frame on the NeRF head (paper Sec. 3.1 + contact refinement) and writes placement.json.
#include <spdlog/spdlog.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "fit/fit_job.h"
#include "host/util/output_folder.h"
#include "mesh/refpoints.h"
#include "tools/lorgnette/command.h"

namespace lorgnette::cli {
namespace {

struct FitArgs {
  std::string model, glasses, output = "placement.json", dataset;
  fit::FitSettings settings;  // the fit's own flags (fit_job.h)
  bool json = false, force = false;
};

// An earlier fit's annotated views (fit/debug_draw.h: view_NN.png and views.txt) are the user's too.
void refuse_existing_debug_views(const std::string& dir, bool force) {
  std::error_code ec;
  if (force || dir.empty() || !std::filesystem::is_directory(dir, ec)) return;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name == "views.txt" || (name.rfind("view_", 0) == 0 && e.path().extension() == ".png"))
      throw std::runtime_error("'" + dir + "' already holds a fit's debug views (" + name +
                               "): pass --force to overwrite them or choose another --debug directory");
  }
}

void run_fit(const FitArgs& a, GlobalOptions& global) {
  fit::FitOptions opt = fit::fit_options(a.settings);  // the numbers' ranges first
  refuse_output_onto_input(a.output, {a.model, a.glasses, mesh::sidecar_path(a.glasses), a.dataset});
  refuse_existing_output(a.output, a.force);  // before minutes of fitting
  refuse_existing_debug_views(a.settings.debug_dir, a.force);
  fit::GlassesInput glasses = fit::load_glasses_input(a.glasses);
  cl::Runtime rt(global.runtime());
  nerf::NerfModel model = nerf::NerfModel::load(rt, a.model);
  fit::NerfViewOptions views;
  views.dataset = a.dataset;
  fit::FitJobResult job = fit::run_fit_job(model, glasses, opt, views);
  const fit::FitResult& r = job.fit;
  const fit::PlacementFile& pf = job.placement;
  fit::write_placement(a.output, pf);
  for (const auto& w : r.warnings) spdlog::warn("fit: {}", w);
  if (a.json) {
    std::cout << fit::to_json(pf).dump(2) << "\n";
  } else {
    std::cerr << "placed " << a.glasses << " (" << r.views_used << "/" << r.views.size() << " views, PD "
              << pf.pd_mm << " mm, " << pf.mm_per_unit << " mm/unit, penetration " << pf.penetration_mm
              << " mm, " << r.total_seconds() << " s" << (pf.ok ? "" : ", NOT ok: see warnings") << ") -> "
              << a.output << "\n";
    std::cerr << fit::scale_summary(pf.scale_source, pf.mm_per_unit, pf.mm_per_unit_uncertainty, pf.pd_mm,
                                    pf.pd_uncertainty_mm, pf.scale_policy)
              << "\n";
    for (const fit::AdviceRule& rule : pf.advice.rules) std::cerr << "  " << rule.text << "\n";
  }
}

void add_fit(CLI::App& app, GlobalOptions& global) {
  auto a = std::make_shared<FitArgs>();
  auto* cmd =
      app.add_subcommand("fit", "place a glasses frame on a trained NeRF head (writes placement.json)");
  cmd->add_option("model", a->model, "trained model (.lnerf)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--glasses", a->glasses, "glasses file (glTF/OBJ/PLY)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", a->output, "placement.json to write")->capture_default_str();
  cmd->add_option("--views", a->settings.views, "number of rendered views K")->capture_default_str();
  cmd->add_option("--yaw-range", a->settings.yaw_range_deg, "views span +-this yaw (deg; dlib works to ~45)")
      ->capture_default_str();
  cmd->add_option("--pitch-range", a->settings.pitch_range_deg, "views span +-this pitch (deg)")
      ->capture_default_str();
  cmd->add_option("--resolution", a->settings.resolution, "front-search view size in pixels (whole head)")
      ->capture_default_str();
  cmd->add_option("--cap-resolution", a->settings.cap_resolution,
                  "size in pixels of the K views framed on the face (0: --resolution)")
      ->capture_default_str()
      ->capture_default_str();
  cmd->add_option("--upsample", a->settings.upsample, "detector up-sampling steps for small faces");
  cmd->add_option(
         "--scale-policy", a->settings.policy,
         "auto (true size with a card's or the irises' scale, else stretch), stretch (paper) or true-size")
      ->capture_default_str();
  cmd->add_option("--dataset", a->dataset,
                  "transforms.json of the capture (prior front/up; default: the model's)");
  cmd->add_option("--mean-face", a->settings.mean_face, "68-point mean face (204 numbers)");
  cmd->add_option("--landmark-model", a->settings.landmark_model, "dlib 68-point shape predictor (.dat)");
  cmd->add_option("--debug", a->settings.debug_dir, "write annotated views to this directory");
  cmd->add_flag("--json", a->json, "print placement.json on stdout");
  cmd->add_flag("--force", a->force, "overwrite an existing placement.json");
  cmd->callback([a, &global] { run_fit(*a, global); });
}

}  // namespace
LGN_REGISTER_COMMAND(60, add_fit);
}  // namespace lorgnette::cli
