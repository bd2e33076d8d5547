// The demo's stages, in order; see pipeline.h.
#include "demo/pipeline.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <filesystem>

#include "fit/fit_job.h"
#include "host/dataset/dataset.h"
#include "host/nerf/train_job.h"
#include "host/nerf/train_settings.h"
#include "host/render/evaluate.h"
#include "host/render/orbit.h"
#include "host/render/render_job.h"
#include "host/render/render_settings.h"
#include "host/render/renderer.h"
#include "host/render/view_plan.h"
#include "host/util/bounds.h"
#include "host/util/chart.h"
#include "host/util/interrupt.h"
#include "host/util/machine.h"
#include "host/util/output_folder.h"
#include "host/util/version.h"
#include "mesh/glasses.h"
#include "mesh/gltf_writer.h"
#include "mesh/parametric.h"
#include "mesh/placed_glasses.h"
#include "mesh/preview.h"
#include "mesh/surface_pass.h"
#include "synth/procedural_head.h"
#include "synth/subject.h"
#include "synth/synthesize.h"

namespace lorgnette::demo {
namespace fs = std::filesystem;
namespace {

// A stage's wall and CPU seconds: the CPU seconds hold on a machine whose cores other programs share.
class Stopwatch {
 public:
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  StageTime stage(const char* name) const { return {name, seconds(), process_cpu_seconds() - cpu_start_}; }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  double cpu_start_ = process_cpu_seconds();
};

const OutputOwner kDemoOutput{"demo", "demo output", ""};

struct Context {
  DemoOptions opt;
  DemoReport report;
  std::string dir;        // where this run writes: the staging folder beside the destination
  std::string final_dir;  // the destination it is swapped into (paths stored in files name this)
  int stage = 0;
  static constexpr int kStages = 5;
  void begin(const char* what) {
    ++stage;
    spdlog::info("[{}/{}] {}", stage, kStages, what);
    if (interrupted()) throw std::runtime_error("interrupted before stage '" + std::string(what) + "'");
  }
  std::string path(const std::string& rel) const { return (fs::path(dir) / rel).string(); }
  std::string final_path(const std::string& rel) const { return (fs::path(final_dir) / rel).string(); }
};

// The demo's training request: the one `lorgnette train` and Python build (train_settings.h), in the
// dataset's own box. Checked up front by run_demo, so a bad --train-steps fails before any work.
nerf::TrainSettings train_settings(const DemoOptions& opt, const std::string& dir) {
  nerf::TrainSettings s;
  s.batch_log2 = opt.quick ? 15 : 16;
  if (opt.train_seconds != 0.0)
    s.seconds = opt.train_seconds;
  else if (opt.train_steps > 0)
    s.steps = opt.train_steps;
  s.seed = static_cast<uint32_t>(opt.seed);
  s.output = (fs::path(dir) / "head.lnerf").string();  // written at the end (and on Ctrl-C)
  s.progress = opt.progress;
  return s;
}

// The orbit the demo renders (render_settings.h), within the directions the capture saw.
render::OrbitSettings orbit_settings(const DemoOptions& opt) {
  render::OrbitSettings o;
  o.width = o.height = static_cast<uint32_t>(opt.orbit_size);
  o.views = static_cast<uint32_t>(opt.orbit_frames);
  o.elevation_deg = 10.0f;
  return o;
}

synth::Subject stage_synthesize(Context& c) {
  c.begin("synthesize a procedural head and render its dataset");
  Stopwatch sw;
  synth::HeadParams params = synth::random_head_params(c.opt.seed);
  synth::Subject subject = synth::procedural_subject(params);
  synth::SynthOptions so;
  so.views = c.opt.views;
  so.width = so.height = c.opt.image_size;
  so.seed = c.opt.seed;
  // Views on 270 degrees around the head, so the orbit shows a complete head, while the mean
  // camera direction still marks the face's front for the fit and the orbit's start.
  so.yaw_min_deg = -135.0f;
  so.yaw_max_deg = 135.0f;
  so.progress = [](int done, int total) { spdlog::debug("synth view {}/{}", done, total); };
  synth::synthesize_dataset(subject, c.path("dataset"), so);
  c.report.stages.push_back(sw.stage("synthesize"));
  c.report.config["subject"] = subject.params;
  return subject;
}

nerf::NerfModel stage_train(Context& c, cl::Runtime& rt, dataset::Dataset& ds) {
  c.begin("train the NeRF head");
  Stopwatch sw;
  nerf::TrainJobResult out = nerf::train_on_dataset(rt, ds, nerf::train_job(train_settings(c.opt, c.dir)));
  const nerf::TrainResult& r = out.result;
  if (r.interrupted)
    throw std::runtime_error("interrupted during training (the model so far is in head.lnerf)");
  // The model names its dataset by absolute path: the one it will have once the output is in place.
  out.model.metadata.dataset_path = c.final_path("dataset");
  out.model.save(c.path("head.lnerf"));
  const nerf::ModelSizing& sizing = out.sizing;
  c.report.train_steps = r.steps;
  c.report.train_seconds = r.seconds;
  c.report.train_budget = out.budget;
  c.report.model_mb = sizing.megabytes();
  std::vector<double> x, y;
  for (size_t i = 0; i < r.loss_curve.size(); ++i) {
    x.push_back(double(i + 1));
    y.push_back(r.loss_curve[i] > 0 ? -10.0 * std::log10(r.loss_curve[i]) : 0.0);
  }
  write_chart(c.path("training_psnr.png"), {"training batch PSNR (sRGB)", "step", "dB"},
              {{"batch PSNR", x, y}});
  c.report.loss_chart = "training_psnr.png";
  c.report.stages.push_back(sw.stage("train"));
  return std::move(out.model);
}

void stage_evaluate(Context& c, nerf::NerfModel& model, dataset::Dataset& ds) {
  c.begin("evaluate on held-out views");
  Stopwatch sw;
  std::vector<nerf::View> views;
  for (const dataset::Frame* f : ds.split(dataset::Split::Holdout)) views.push_back({f->camera, &f->image});
  render::EvalOptions eo;
  eo.max_views = c.opt.quick ? 3 : 6;
  eo.output_dir = c.path("heldout");
  fs::create_directories(eo.output_dir);
  render::EvalResult e = render::evaluate(model, views, eo);
  c.report.psnr = e.psnr;
  c.report.ssim = e.ssim;
  c.report.heldout_views = static_cast<int>(e.views);
  for (const auto& entry : fs::directory_iterator(eo.output_dir))
    c.report.heldout_images.push_back("heldout/" + entry.path().filename().string());
  std::sort(c.report.heldout_images.begin(), c.report.heldout_images.end());
  spdlog::info("held-out PSNR {:.2f} dB, SSIM {:.3f} over {} views", e.psnr, e.ssim, e.views);
  c.report.stages.push_back(sw.stage("evaluate"));
}

std::string stage_glasses(Context& c) {
  if (!c.opt.glasses.empty()) return c.opt.glasses;
  mesh::FrameParams fp;  // 52-18-140 rectangular, black: a common size
  mesh::ParametricFrame frame = mesh::make_parametric_frame(fp);
  std::string path = c.path("frame.glb");
  mesh::write_glb(path, frame.mesh);
  mesh::RefPointsSidecar sidecar;  // file coordinates of a .glb are metres
  sidecar.points = frame.ref;
  sidecar.points.g_l /= 1000.0f, sidecar.points.g_r /= 1000.0f;
  mesh::write_refpoints_sidecar(path, sidecar);
  return path;
}

fit::FitResult stage_fit(Context& c, nerf::NerfModel& model, const std::string& glasses_path,
                         const synth::Subject& subject) {
  c.begin("fit the glasses on the NeRF head");
  Stopwatch sw;
  // The fit request every front end builds (fit_job.h: the CLI's defaults), with the demo's views.
  fit::FitSettings settings;
  settings.views = c.opt.fit_views;
  settings.debug_dir = c.path("fit-debug");
  const fit::FitOptions fo = fit::fit_options(settings);
  fs::create_directories(fo.debug_dir);
  fit::NerfViewOptions views;
  views.dataset = c.path("dataset/transforms.json");
  fit::FitJobResult job = fit::run_fit_job(model, glasses_path, fo, views);
  const fit::FitResult& r = job.fit;
  fit::PlacementFile pf = job.placement;
  // The demo's own frame beside placement.json (a relative path is read from the placement's
  // folder), a given one by absolute path: both stay right once the output is moved into place.
  pf.glasses_path = c.opt.glasses.empty() ? "frame.glb" : fs::absolute(c.opt.glasses).string();
  fit::write_placement(c.path("placement.json"), pf);
  c.report.fit = fit::to_json(pf);
  for (const auto& w : r.warnings) spdlog::warn("fit: {}", w);
  for (const auto& entry : fs::directory_iterator(fo.debug_dir))
    c.report.debug_views.push_back("fit-debug/" + entry.path().filename().string());
  std::sort(c.report.debug_views.begin(), c.report.debug_views.end());

  // Against the synthetic head's exact landmarks (dataset frame = model frame * 1/scale - offset).
  const double mm = subject.mm_per_unit.value_or(0.0);
  auto to_model = [&](const Eigen::Vector3f& p) {
    Eigen::Vector3d q = p.cast<double>() * model.normalisation.scale;
    for (int i = 0; i < 3; ++i) q[i] += model.normalisation.offset[i];
    return q;
  };
  nlohmann::json gt = nlohmann::json::object();
  auto compare = [&](const std::string& key, const char* fit_name, const Eigen::Vector3f& truth) {
    auto f = r.landmarks.find(fit_name);
    if (f == r.landmarks.end() || mm <= 0) return;
    gt[key] = (f->second.position - to_model(truth)).norm() * mm;
  };
  auto truth = [&](const char* name) { return subject.landmarks.at(name); };
  // f_c is defined as the midpoint of iBUG 27 and 28 (fit/ears.h); the head knows both exactly.
  if (subject.ibug68.size() == 68)
    compare("nose_error_mm", "nose", 0.5f * (subject.ibug68[27] + subject.ibug68[28]));
  compare("eye_l_error_mm", "eye_l", truth("eye_l_outer"));
  compare("eye_r_error_mm", "eye_r", truth("eye_r_outer"));
  // The fit's ears (the density's ear roots, fit/ear_root.h, or Eq. 2-3 where it shows none) against
  // the head's anatomical ear rests (synth's, on the ear's top a few mm outside the crease).
  compare("ear_l_vs_anatomical_mm", "ear_l", truth("ear_rest_l"));
  compare("ear_r_vs_anatomical_mm", "ear_r", truth("ear_rest_r"));
  gt["mm_per_unit_true"] = mm;
  // The fit's scale (per model unit) and PD against the head's exact ones (#44).
  if (mm > 0 && model.normalisation.scale > 0)
    gt["mm_per_unit_error_percent"] = 100.0 * (pf.mm_per_unit * model.normalisation.scale / mm - 1.0);
  if (mm > 0 && subject.landmarks.count("pupil_l") && subject.landmarks.count("pupil_r")) {
    const double pd = (subject.landmarks.at("pupil_l") - subject.landmarks.at("pupil_r")).norm() * mm;
    gt["pd_true_mm"] = pd;
    gt["pd_error_mm"] = pf.pd_mm - pd;
  }
  c.report.ground_truth = gt;
  c.report.stages.push_back(sw.stage("fit"));
  return std::move(job.fit);
}

void stage_render(Context& c, cl::Runtime& rt, nerf::NerfModel& model, const std::string& glasses_path,
                  const fit::FitResult& fitted, const dataset::Dataset& ds) {
  c.begin("render the orbit with the glasses");
  Stopwatch sw;
  render::RenderJob job;
  job.out_dir = c.path("orbit");
  std::vector<Camera> cams;
  for (const auto& f : ds.frames) cams.push_back(f.camera);
  render::OrbitPlan plan =
      render::plan_model_orbit(model, orbit_settings(c.opt), render::model_view_range(model), cams);
  for (const auto& note : plan.notes) spdlog::info("orbit: {}", note);
  job.cameras = render::orbit_cameras(plan.spec);
  // canonical mm -> scene, temples spread as the fit chose
  mesh::PlacedGlasses placed =
      mesh::load_placed_glasses(glasses_path, fitted.placement.transform, fitted.temples.bend);
  const mesh::Glasses& g = placed.glasses;
  render::RenderSettings look;  // the CLI's defaults: white background, spp 1, 4 glasses samples
  job.options = render::render_options(look);
  mesh::SurfaceParams sp;
  sp.samples_per_pixel = int(look.surface_spp);
  job.surfaces = [&placed, sp](const Camera& cam) { return placed.pass->render(cam, sp); };
  render::Renderer renderer(rt);
  nlohmann::json summary =
      render::run_render_job(job, [&](const Camera& cam, const lorgnette::SurfaceBuffers* s) {
        return renderer.render(model, cam, s, job.options);
      });
  c.report.config["render"] = summary;
  c.report.orbit_mp4 = fs::exists(c.path("orbit/orbit.mp4")) ? "orbit/orbit.mp4" : "";
  c.report.contact_sheet = fs::exists(c.path("orbit/contact_sheet.png")) ? "orbit/contact_sheet.png" : "";
  Image preview = mesh::render_glasses_preview(g);
  write_image(c.path("glasses_preview.png"), preview);
  c.report.glasses_preview = "glasses_preview.png";
  c.report.stages.push_back(sw.stage("render"));
}

}  // namespace

DemoOptions defaults_for(DemoOptions o) {
  auto pick = [&](auto& v, auto full, auto quick) {
    if (v <= 0) v = o.quick ? quick : full;
  };
  pick(o.views, 48, 32);
  pick(o.image_size, 192, 128);
  // Full: the size-based default (2000 steps of 2^16 samples on the demo head, ~35 dB held-out).
  // Quick: 600 steps of 2^15, ~55 s on the 2-core Xeon and 31.7 dB held-out (1200 steps: 107 s,
  // 32.7 dB), so the whole quick demo stays within its 2 minutes (BENCHMARKS.md).
  if (o.train_steps == 0 && !(o.train_seconds > 0.0) && o.quick) o.train_steps = 600;
  pick(o.orbit_frames, 36, 8);
  pick(o.orbit_size, 320, 192);
  pick(o.fit_views, 12, 8);
  return o;
}

namespace {

void run_stages(Context& c, cl::Runtime& rt) {
  synth::Subject subject = stage_synthesize(c);
  dataset::Dataset ds = dataset::load_dataset(c.path("dataset"));
  nerf::NerfModel model = stage_train(c, rt, ds);
  stage_evaluate(c, model, ds);
  std::string glasses = stage_glasses(c);
  fit::FitResult fitted = stage_fit(c, model, glasses, subject);
  stage_render(c, rt, model, glasses, fitted, ds);
  c.report.ok = fitted.ok;
  c.report.message = fitted.ok ? "" : "the fit reported problems: see the warnings in fit.warnings";
}

}  // namespace

DemoReport run_demo(const DemoOptions& options, const cl::RuntimeOptions& runtime) {
  Context c;
  c.opt = defaults_for(options);
  c.report.version = fmt::format("{} (commit {})", version_string(), git_commit());
  c.report.machine = machine_info().summary();  // the load before the demo adds its own
  c.report.config = {{"quick", c.opt.quick},
                     {"views", c.opt.views},
                     {"image_size", c.opt.image_size},
                     {"train_steps", c.opt.train_steps},
                     {"train_seconds", c.opt.train_seconds},
                     {"orbit_frames", c.opt.orbit_frames},
                     {"orbit_size", c.opt.orbit_size},
                     {"fit_views", c.opt.fit_views},
                     {"seed", c.opt.seed}};
  // The flags' ranges (host/util/bounds.h) before anything is written.
  check_bound(bounds::kDemoViews, c.opt.views);
  check_bound(bounds::kDemoImageSize, c.opt.image_size);
  check_bound(bounds::kDemoOrbitSize, c.opt.orbit_size);
  check_bound(bounds::kDemoFitViews, c.opt.fit_views);
  nerf::validate(train_settings(c.opt, c.dir));
  render::validate(orbit_settings(c.opt));
  // Inputs inside the output folder are refused before anything starts (the swap would delete them).
  StagedOutput staged(c.opt.out_dir, kDemoOutput, c.opt.force, {c.opt.glasses});
  c.dir = staged.path();
  c.final_dir = staged.destination();
  cl::Runtime rt(runtime);
  c.report.device = rt.device().summary();
  try {
    run_stages(c, rt);
  } catch (const std::exception& e) {
    c.report.ok = false;
    c.report.message = e.what();
    // A failed run is kept (its report says ok = false) only where it replaces nothing; an earlier
    // output stays whole and the staging folder is removed.
    if (staged.replaces_earlier())
      throw std::runtime_error(
          fmt::format("{}; the earlier demo output in '{}' is unchanged", e.what(), c.opt.out_dir));
    try {
      write_report(c.dir, c.report);
      staged.commit();
    } catch (const std::exception& also) {
      spdlog::error("could not keep the failed run's output: {}", also.what());
    }
    throw;
  }
  write_report(c.dir, c.report);
  staged.commit();
  return c.report;
}

}  // namespace lorgnette::demo
