// The service's calls into capture, train and fit (product_calls.h).
#include "service/product_calls.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <stdexcept>

#include "capture/capture.h"
#include "capture/subject_box.h"
#include "fit/fit_job.h"
#include "fit/head_framing.h"
#include "fit/placement_json.h"
#include "host/dataset/dataset.h"
#include "host/nerf/train_job.h"
#include "host/render/render_settings.h"
#include "host/render/renderer.h"
#include "host/util/image_io.h"
#include "host/util/interrupt.h"
#include "mesh/placed_glasses.h"

namespace fs = std::filesystem;

namespace lorgnette::service {

fs::path capture_input(const fs::path& upload_dir) {
  if (fs::is_directory(upload_dir / "images")) return upload_dir / "images";
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(upload_dir, ec))
    if (e.is_regular_file() && e.path().stem() == "video") return e.path();
  throw std::runtime_error(
      "nothing was uploaded for this capture: upload a video of a head turn from ear to ear, or photos");
}

void capture_dataset(const fs::path& input, const fs::path& output_dir, const JobSettings& settings) {
  capture::CaptureOptions o;
  o.input = input.string();
  o.output = output_dir.string();
  o.force = true;  // the stage's own fresh temporary folder
  o.frames.fps = settings.capture_fps;
  o.frames.max_frames = settings.capture_max_frames;
  o.frames.max_side = settings.capture_max_side;
  capture::CaptureReport report = capture::run_capture(o);
  spdlog::info("capture: {} of {} frames posed", report.registered, report.candidate_frames);
}

void train_model(cl::Runtime& rt, const fs::path& dataset_dir, const fs::path& model_file,
                 const fs::path& checkpoint, const JobSettings& settings,
                 const std::function<void(double)>& on_fraction) {
  dataset::LoadOptions lo;
  lo.max_side = settings.train_max_side;
  lo.max_image_bytes = nerf::kTrainImageBytes;
  lo.splits = {dataset::Split::Train};
  dataset::Dataset ds = dataset::load_dataset(dataset_dir.string(), lo);
  nerf::TrainJob job;
  capture::apply_subject_box(ds, capture::BoxSource::Auto, true, job);
  job.batch_log2 = settings.train_batch_log2;
  job.train.steps = settings.train_steps;
  job.train.seed = settings.train_seed;
  job.train.snapshot_path = model_file.string();
  job.train.snapshot_every_seconds = settings.train_snapshot_seconds;
  // A retried job continues its training (a checkpoint that does not match is trained over), and the
  // stage removes the checkpoint once the model is in place.
  job.train.checkpoint_path = checkpoint.string();
  job.resume = nerf::TrainJob::Resume::IfValid;
  job.keep_checkpoint = true;
  job.train.progress = false;
  uint64_t budget = settings.train_steps;  // 0: the product's default budget, known once planned
  job.on_planned = [&](uint64_t steps) { budget = steps; };
  job.train.on_step = [&](uint64_t step, double, double) {
    if (budget > 0) on_fraction(double(step) / double(budget));
  };
  nerf::TrainJobResult out = nerf::train_on_dataset(rt, ds, job);
  if (out.result.interrupted) return;  // the caller sees interrupted() and keeps nothing
  spdlog::info("train: {} steps in {:.1f} s ({})", out.result.steps, out.result.seconds, out.budget);
}

bool fit_frame(cl::Runtime& rt, const fs::path& model_file, const fs::path& dataset_dir,
               const std::string& glasses, const fs::path& output_dir, const JobSettings& settings) {
  fit::FitSettings fs_settings;
  fs_settings.views = settings.fit_views;
  fs_settings.resolution = settings.fit_resolution;
  fit::FitOptions options = fit::fit_options(fs_settings);
  nerf::NerfModel model = nerf::NerfModel::load(rt, model_file.string());
  fit::NerfViewOptions views;
  views.dataset = (dataset_dir / "transforms.json").string();
  fit::FitJobResult job = fit::run_fit_job(model, glasses, options, views);
  fit::write_placement((output_dir / "placement.json").string(), job.placement);
  for (const auto& w : job.fit.warnings) spdlog::warn("fit {}: {}", glasses, w);
  return job.placement.ok;
}

std::vector<std::string> render_tryon_views(cl::Runtime& rt, const fs::path& model_file,
                                            const std::string& glasses, const fs::path& placement_file,
                                            const fs::path& output_dir, const JobSettings& settings) {
  nerf::NerfModel model = nerf::NerfModel::load(rt, model_file.string());
  const fit::PlacementFile p = fit::read_placement(placement_file.string());
  render::OrbitSettings orbit;
  orbit.views = uint32_t(settings.tryon_views);
  orbit.width = orbit.height = uint32_t(settings.tryon_size);
  orbit.subject = fit::head_framing(p);
  orbit.front = fit::head_front(p);  // the first view faces the face (clamped into the captured arc)
  render::OrbitPlan plan = render::plan_model_orbit(model, orbit, render::model_view_range(model));
  for (const auto& note : plan.notes) spdlog::info("try-on orbit: {}", note);
  render::RenderSettings rs;  // the CLI's defaults: white background, 4 surface samples per pixel
  const render::RenderOptions options = render::render_options(rs);
  mesh::PlacedGlasses placed = mesh::load_placed_glasses(glasses, p.transform, p.temples.bend);
  mesh::SurfaceParams sp;
  sp.samples_per_pixel = int(rs.surface_spp);
  render::Renderer renderer(rt);
  std::vector<std::string> names;
  const std::vector<Camera> cams = render::orbit_cameras(plan.spec);
  for (size_t i = 0; i < cams.size(); ++i) {
    const lorgnette::SurfaceBuffers surfaces = placed.pass->render(cams[i], sp);
    const render::RenderResult r = renderer.render(model, cams[i], &surfaces, options);
    names.push_back(fmt::format("view_{:02d}.jpg", i));
    write_image((output_dir / names.back()).string(), r.rgba);
  }
  return names;
}

}  // namespace lorgnette::service
