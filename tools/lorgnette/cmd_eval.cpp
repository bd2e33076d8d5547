// `lorgnette eval MODEL DATA`: PSNR and SSIM of a trained model over held-out views (test split for
// NeRF-synthetic, every 8th frame of a transforms.json), optional prediction|truth|error images,
// `--holes` (the self-check's regions judged on the evaluated views) and `--json` for scripts.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include "capture/subject_box.h"
#include "host/dataset/dataset.h"
#include "host/nerf/subject_holes.h"
#include "host/render/evaluate.h"
#include "host/render/matte_eval.h"
#include "host/render/renderer.h"
#include "host/util/bounds.h"
#include "host/util/interrupt.h"
#include "synth/matte.h"
#include "tools/lorgnette/command.h"

namespace lorgnette::cli {
namespace {

struct EvalArgs {
  std::string model, data, split, output;
  int max_views = 0, downscale = 1, max_side = 0;  // signed, so -1 is refused with the range
  bool json = false, black = false, force = false, holes = false;
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
      throw std::runtime_error(
          fmt::format("'{}' already holds evaluation images ({} ...): pass --force to "
                      "overwrite them or choose another -o",
                      a.output, name));
  }
}

// Synthetic room captures (synth --room) carry true mattes ("eval_matte_path"), subject depth and
// the 68 landmarks: score the rendered opacity against them (host/render/matte_eval.h). Returns
// null when the dataset has no mattes.
nlohmann::json matte_scores(nerf::NerfModel& model, const dataset::Dataset& ds,
                            const std::vector<const dataset::Frame*>& frames) {
  namespace fs = std::filesystem;
  fs::path root = fs::is_directory(ds.root) ? fs::path(ds.root) : fs::path(ds.root).parent_path();
  const std::map<std::string, synth::EvalFiles> by_stem = synth::eval_files_by_stem(root.string());
  if (by_stem.empty()) return nullptr;
  std::vector<Eigen::Vector3f> face;
  std::ifstream gf(root / "ground_truth.json");
  if (gf) {
    nlohmann::json gt = nlohmann::json::parse(gf, nullptr, false);
    if (!gt.is_discarded() && gt.contains("ibug68"))
      for (const auto& p : gt["ibug68"])
        face.emplace_back(p[0].get<float>(), p[1].get<float>(), p[2].get<float>());
  }
  render::Renderer renderer(model.runtime());
  render::RenderOptions ro;
  std::vector<render::MatteScore> scores;
  for (const dataset::Frame* f : frames) {
    if (interrupted()) throw std::runtime_error("interrupted: the evaluation stopped before its scores");
    auto it = by_stem.find(fs::path(f->image_path).stem().string());
    if (it == by_stem.end()) continue;
    Image matte = synth::read_matte((root / it->second.matte).string());
    Image depth;
    if (!it->second.depth.empty() && fs::exists(root / it->second.depth))
      depth = read_image((root / it->second.depth).string());
    if (matte.width != int(f->camera.width) || matte.height != int(f->camera.height)) continue;  // downscaled
    Image pred = renderer.render(model, f->camera, nullptr, ro).rgba;
    render::MatteView v{f->camera, &pred, &f->image, &matte, depth.empty() ? nullptr : &depth, face};
    scores.push_back(render::score_matte(v, model.aabb()));
  }
  if (scores.empty()) return nullptr;
  render::MatteScore m = render::mean_score(scores);
  nlohmann::json per = nlohmann::json::array();
  for (const auto& s : scores)
    per.push_back({{"iou", s.iou},
                   {"leak", s.leak},
                   {"leak_excess", s.leak_excess},
                   {"face_psnr", s.face_psnr},
                   {"face_psnr_covered", s.face_psnr_subject},
                   {"holes", s.holes}});
  return {{"iou", m.iou},
          {"leak", m.leak},
          {"leak_excess", m.leak_excess},
          {"face_psnr", m.face_psnr},
          // over the face hull's pixels the subject covers fully: the whole hull's rim holds room
          {"face_psnr_covered", m.face_psnr_subject},
          {"holes", m.holes},
          {"holes_worst_view", m.holes_worst},
          {"holes_region", "the matte eroded 7 px, upper 45 % of the subject's rows; opacity < 0.5"},
          {"views", scores.size()},
          {"region", "subject inside the model's box (head to neck); opacity >= 0.5 vs matte >= 0.5"},
          {"per_view", per}};
}

// Holes in the head seen from the evaluated views (host/nerf/subject_holes.h): the regions training's
// self-check judges (the face's landmark hull and the head's certain interior), from the landmark head
// box of the dataset's training photos, marched through the model from every evaluated view. On a
// capture without true mattes (a real one) this is the held-out figure.
nerf::HoleReport held_out_holes(nerf::NerfModel& model, const EvalArgs& a, const dataset::LoadOptions& lo,
                                const std::vector<nerf::View>& views) {
  dataset::LoadOptions train = lo;
  train.splits = {dataset::Split::Train};
  const dataset::Dataset photos = dataset::load_dataset(a.data, train);
  const capture::SubjectBoxChoice box = capture::choose_subject_box(photos, capture::BoxSource::Head, false);
  if (!box.zones || box.zones->whole.empty())
    throw std::runtime_error(
        "--holes: no face was found in enough of the dataset's training photos to place the head's "
        "regions (the landmark head box); evaluate without --holes, or give a capture whose photos show "
        "the face");
  std::vector<Camera> cams;
  for (const nerf::View& v : views) cams.push_back(v.camera);
  nerf::HoleCheckOptions o;
  o.max_views = cams.size();
  return nerf::check_subject_holes(model, cams, box.zones->whole, o);
}

// --holes as JSON: the worst region's share, the worst view's, and each region's rays and share.
nlohmann::json holes_json(const nerf::HoleReport& r) {
  nlohmann::json regions = nlohmann::json::object();
  for (const nerf::RegionHoles& g : r.regions) regions[g.name] = {{"rays", g.rays}, {"holes", g.share()}};
  return {{"holes", r.holes}, {"worst_view", r.worst_view}, {"regions", regions}};
}

void run_eval(const EvalArgs& a, GlobalOptions& global) {
  check_bound_or_zero(bounds::kEvalMaxViews, a.max_views);  // host/util/bounds.h, before any loading
  check_bound(bounds::kDownscale, a.downscale);
  check_bound_or_zero(bounds::kMaxSide, a.max_side);
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
  eo.max_views = uint32_t(a.max_views);
  eo.output_dir = a.output;
  if (a.black) eo.background = {0.0f, 0.0f, 0.0f};
  render::EvalResult r = render::evaluate(model, views, eo);
  nlohmann::json mattes = matte_scores(model, ds, ds.require_split(split));
  std::optional<nerf::HoleReport> holes;
  if (a.holes) holes = held_out_holes(model, a, lo, views);
  if (a.json) {
    nlohmann::json out = {{"psnr", r.psnr},
                          {"ssim", r.ssim},
                          {"views", r.views},
                          {"split", dataset::to_string(split)},
                          {"train_seconds", model.metadata.train_seconds},
                          {"steps", model.metadata.steps},
                          {"eval_seconds", r.seconds},
                          {"view_psnr", r.view_psnr},
                          {"view_ssim", r.view_ssim},
                          {"model", a.model}};
    if (!mattes.is_null()) out["mattes"] = mattes;
    if (holes) out["held_out_holes"] = holes_json(*holes);
    if (!model.metadata.subject_problem.empty()) out["subject_problem"] = model.metadata.subject_problem;
    // Training's check of its own output (host/nerf/subject_holes.h); null when it did not run.
    out["holes"] = model.metadata.holes >= 0.0 ? nlohmann::json(model.metadata.holes) : nlohmann::json();
    out["holes_worst_view"] = model.metadata.holes_worst_view >= 0.0
                                  ? nlohmann::json(model.metadata.holes_worst_view)
                                  : nlohmann::json();
    std::cout << out.dump() << "\n";
  } else {
    std::cout << fmt::format(
        "{} views ({}): PSNR {:.2f} dB, SSIM {:.4f} (model: {} steps, {:.0f} s training)\n", r.views,
        dataset::to_string(split), r.psnr, r.ssim, model.metadata.steps, model.metadata.train_seconds);
    if (!mattes.is_null())
      std::cout << fmt::format(
          "true mattes ({} views, head to neck inside the model's box): IoU {:.4f}, leak {:.2f} % "
          "of the subject's area ({:.2f} % beyond the matte's own coverage), face PSNR {:.2f} dB "
          "({:.2f} dB where the subject covers the face's pixels fully), holes {:.2f} % of the head's "
          "interior (worst view {:.2f} %)\n",
          mattes["views"].get<int>(), mattes["iou"].get<double>(), 100.0 * mattes["leak"].get<double>(),
          100.0 * mattes["leak_excess"].get<double>(), mattes["face_psnr"].get<double>(),
          mattes["face_psnr_covered"].get<double>(), 100.0 * mattes["holes"].get<double>(),
          100.0 * mattes["holes_worst_view"].get<double>());
  }
  if (!a.json)
    std::cout << (model.metadata.holes >= 0.0
                      ? fmt::format(
                            "holes in the face and head (training's self-check, training views): {:.2f} % "
                            "transparent, worst view {:.2f} %\n",
                            100.0 * model.metadata.holes, 100.0 * model.metadata.holes_worst_view)
                      : std::string("holes in the face and head: not checked (no room model or no face "
                                    "landmarks in training)\n"));
  if (holes && !a.json) std::cout << "evaluated views: " << holes->summary() << "\n";
  if (!a.output.empty()) spdlog::info("prediction | truth | error images in '{}'", a.output);
  // The scores judge the pixels, not whether the subject was separated: say so when it was not.
  if (!model.metadata.subject_problem.empty())
    spdlog::warn("this model is not a separated subject: {}", model.metadata.subject_problem);
}

void add_eval(CLI::App& app, GlobalOptions& global) {
  auto* cmd = app.add_subcommand("eval", "PSNR / SSIM of a trained model on held-out views");
  auto a = std::make_shared<EvalArgs>();
  cmd->add_option("MODEL", a->model, "model file (.lnerf)")->required();
  cmd->add_option("DATA", a->data, "dataset directory or json file")->required();
  cmd->add_option("--split", a->split,
                  "test | val | holdout (default: test, or holdout for transforms.json)");
  cmd->add_option("-o,--output", a->output, "directory for prediction|truth|error images");
  cmd->add_option("--max-views", a->max_views, "evaluate at most this many views, evenly spaced");
  cmd->add_option("--downscale", a->downscale, "integer image downscale factor (as in training)");
  cmd->add_option("--max-side", a->max_side, "shrink images so the longer side is at most this");
  cmd->add_flag("--black", a->black, "black background instead of white for RGBA truth");
  cmd->add_flag(
      "--holes", a->holes,
      "also measure holes in the head from the evaluated views: the regions training's self-check "
      "judges (face landmark hull, the head's certain interior), from the training photos' landmarks");
  cmd->add_flag("--json", a->json, "print one JSON object on stdout");
  cmd->add_flag("--force", a->force, "overwrite evaluation images already in the -o directory");
  cmd->callback([a, &global] { run_eval(*a, global); });
}

}  // namespace
LGN_REGISTER_COMMAND(21, add_eval);
}  // namespace lorgnette::cli
