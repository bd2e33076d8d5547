// `lorgnette render MODEL [--glasses FRAME --placement P.json | --transform 4x4 | --translate x y z
// --rotate rx ry rz --scale s] (--orbit N | --pose JSON) --size WxH [--spp N] [--alpha] -o DIR`:
// try-on renders of a trained head with a glasses frame (host/render/render_job.h does the work).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <Eigen/Core>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "fit/head_framing.h"
#include "fit/placement_json.h"
#include "fit/placement_transform.h"
#include "host/dataset/dataset.h"
#include "host/nerf/model.h"
#include "host/render/render_job.h"
#include "host/render/render_settings.h"
#include "host/render/renderer.h"
#include "host/render/view_plan.h"
#include "host/util/bounds.h"
#include "host/util/file_write.h"
#include "host/util/output_folder.h"
#include "mesh/placed_glasses.h"
#include "tools/lorgnette/command.h"

namespace lorgnette::cli {
namespace {

struct RenderArgs {
  std::string model, glasses, placement, transform, pose, out;
  std::string size = fmt::format("{}x{}", render::OrbitSettings{}.width, render::OrbitSettings{}.height);
  std::vector<float> translate, rotate, background, front;
  float scale = 1.0f;
  render::RenderSettings render;  // checked by render::validate (host/util/bounds.h), as Python's are
  render::OrbitSettings orbit;    // orbit.views = --orbit (0: a --pose camera instead)
  bool force = false, json = false, no_video = false;
};

render::Vec3 vec3(const std::vector<float>& v, render::Vec3 fallback) {
  return v.empty() ? fallback : render::Vec3{v[0], v[1], v[2]};
}

// The placement transform (canonical mm -> scene), and the temple spread when it comes from a
// placement.json (read by the placement module, fit/placement_json.h, which refuses broken
// transforms). A placement fitted for another glasses file than the one rendered gets a warning.
fit::Transform glasses_transform(const RenderArgs& a, std::string& glasses_path, mesh::TempleBend& temples) {
  int given = !a.placement.empty() + !a.transform.empty() +
              (!a.translate.empty() || !a.rotate.empty() || a.scale != 1.0f);
  if (given > 1)
    throw std::runtime_error("give one of --placement, --transform, or --translate/--rotate/--scale");
  if (!a.placement.empty()) {
    fit::PlacementFile p = fit::read_placement(a.placement);
    if (glasses_path.empty()) {
      glasses_path = p.glasses_path;
      if (!glasses_path.empty() && !std::filesystem::exists(glasses_path))
        throw std::runtime_error("placement '" + a.placement + "' names the glasses '" + glasses_path +
                                 "' (relative to the placement's folder), which does not exist: pass "
                                 "--glasses FRAME");
    }
    if (!glasses_path.empty())
      if (std::string why = fit::glasses_mismatch(p, glasses_path); !why.empty()) spdlog::warn("{}", why);
    temples = p.temples.bend;
    return p.transform;
  }
  if (!a.transform.empty()) return fit::parse_transform(a.transform);
  return fit::trs_transform(vec3(a.translate, {0, 0, 0}), vec3(a.rotate, {0, 0, 0}), a.scale);
}

// The request's checks, and the outputs' (a user's files are refused before any work: device, model,
// glasses); fills the orbit's size from --size.
void check_request(RenderArgs& a) {
  const bool orbit = a.orbit.views > 0;
  if (orbit == !a.pose.empty()) throw std::runtime_error("give either --orbit N or --pose JSON");
  if (!a.front.empty()) {
    if (!orbit)
      throw std::runtime_error(
          "--front says where an --orbit starts: give --orbit N too (a --pose camera is placed by its own "
          "transform_matrix)");
    a.orbit.front = vec3(a.front, {});
  }
  auto size = render::parse_size(a.size);
  a.orbit.width = size[0], a.orbit.height = size[1];
  if (!a.background.empty()) a.render.background = vec3(a.background, {1, 1, 1});
  render::validate(a.render);
  if (orbit)
    render::validate(a.orbit);
  else
    check_bound(bounds::kFovDeg, a.orbit.fov_y_deg);
  render::RenderJob planned;
  planned.video = !a.no_video;
  planned.cameras.resize(orbit ? a.orbit.views : 1);
  render::check_outputs_free(a.out, render::render_job_outputs(planned), a.force);
  // A read-only folder or a full disk is found now, not after the model loaded and a view rendered.
  check_writable_folder(nearest_existing_folder(a.out).string(), fmt::format("the renders (-o {})", a.out));
}

void run(RenderArgs& a, GlobalOptions& global) {
  check_request(a);
  const bool orbit = a.orbit.views > 0;
  cl::Runtime rt(global.runtime());
  nerf::NerfModel model = nerf::NerfModel::load(rt, a.model);

  render::RenderJob job;
  job.out_dir = a.out;
  job.force = a.force;
  job.video = !a.no_video;
  job.options = render::render_options(a.render);
  std::string range_source;
  std::optional<nerf::ViewRange> range = render::model_view_range(model, &range_source);
  if (range) spdlog::info("captured directions: {} from {}", range->summary(), range_source);
  if (orbit && !a.placement.empty()) {
    // A placement knows where the head is: the orbit frames the head, not the model's whole box.
    a.orbit.subject = fit::head_framing(fit::read_placement(a.placement));
    spdlog::info("orbit: framing the head the placement sits on");
  }
  if (orbit) {
    render::OrbitPlan plan = render::plan_model_orbit(model, a.orbit, range);
    for (const auto& note : plan.notes) spdlog::info("orbit: {}", note);
    job.cameras = render::orbit_cameras(plan.spec);
  } else {
    job.cameras = {render::read_pose(a.pose, a.orbit.width, a.orbit.height, a.orbit.fov_y_deg)};
    if (std::string note = render::pose_outside_note(job.cameras[0], range); !note.empty())
      spdlog::warn("{}", note);
  }

  std::string glasses_path = a.glasses;
  mesh::TempleBend temples;
  fit::Transform placement = glasses_transform(a, glasses_path, temples);
  const bool placed = !a.placement.empty() || !a.transform.empty() || !a.translate.empty() ||
                      !a.rotate.empty() || a.scale != 1.0f;
  render::check_glasses_and_placement(!glasses_path.empty(), placed);
  std::unique_ptr<mesh::SurfacePass> pass;
  if (!glasses_path.empty()) {
    pass = mesh::load_placed_glasses(glasses_path, placement, temples).pass;
    mesh::SurfaceParams sp;
    sp.samples_per_pixel = int(a.render.surface_spp);
    job.surfaces = [&pass, sp](const Camera& cam) { return pass->render(cam, sp); };
  }

  render::Renderer renderer(rt);
  nlohmann::json summary =
      render::run_render_job(job, [&](const Camera& cam, const lorgnette::SurfaceBuffers* s) {
        return renderer.render(model, cam, s, job.options);
      });
  summary["model"] = a.model;
  if (!glasses_path.empty()) summary["glasses_path"] = glasses_path;
  summary["device"] = rt.device().name;
  if (a.json)
    std::cout << summary.dump(2) << "\n";
  else
    spdlog::info("wrote {} view(s) to {} (median {:.0f} ms/frame, {:.1f} samples/ray)", job.cameras.size(),
                 a.out, summary["median_march_ms"].get<double>(), summary["samples_per_ray"].get<double>());
}

void add_render(CLI::App& app, GlobalOptions& global) {
  auto a = std::make_shared<RenderArgs>();
  a->orbit.views = 0;  // no --orbit: a --pose camera
  auto* cmd = app.add_subcommand("render", "render a trained head (.lnerf) with or without glasses");
  cmd->add_option("model", a->model, "trained model snapshot (.lnerf)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--glasses", a->glasses, "glasses frame (glTF/GLB/OBJ/PLY)")->check(CLI::ExistingFile);
  cmd->add_option("--placement", a->placement, "placement.json from `lorgnette fit`")
      ->check(CLI::ExistingFile);
  cmd->add_option("--transform", a->transform, "canonical mm -> scene, 16 numbers row-major");
  cmd->add_option("--translate", a->translate, "glasses translation (scene units)")->expected(3);
  cmd->add_option("--rotate", a->rotate, "glasses rotation about x, y, z (degrees, applied x then y then z)")
      ->expected(3);
  cmd->add_option("--scale", a->scale, "scene units per millimetre of the frame");
  cmd->add_option(
      "--orbit", a->orbit.views,
      "N views around the head (1..3600), starting at its front, within the directions the "
      "capture saw (plus a margin); with --placement the orbit frames the head (fit/head_framing.h), "
      "else the model's box");
  cmd->add_option("--pose", a->pose, "one camera: JSON with transform_matrix (+ fl_x, w, h or fov_y_deg)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--size", a->size, "image size WIDTHxHEIGHT")->capture_default_str();
  // The ranges are render::validate's (host/util/bounds.h), the same in Python.
  cmd->add_option("--spp", a->render.spp, "NeRF rays per pixel (1..64)")->capture_default_str();
  cmd->add_option("--surface-spp", a->render.surface_spp, "glasses samples per pixel, anti-aliasing (1..256)")
      ->capture_default_str();
  cmd->add_option("--step-scale", a->render.step_scale,
                  "marching step multiplier, >1 faster, coarser (0.25..8)")
      ->capture_default_str();
  cmd->add_option("--marcher", a->render.marcher,
                  "auto (fused on a GPU, wavefront on a CPU), wavefront or fused")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "wavefront", "fused"}));
  cmd->add_option("--fov", a->orbit.fov_y_deg, "vertical field of view, degrees (5..120)")
      ->capture_default_str();
  cmd->add_option("--elevation", a->orbit.elevation_deg, "orbit elevation, degrees (-80..80)")
      ->capture_default_str();
  cmd->add_option(
         "--front", a->front,
         "the first view's direction from the head (default: the capture's mean camera); its tilt adds "
         "to --elevation; clamped into the captured directions unless --beyond-capture")
      ->expected(3);
  cmd->add_flag("--beyond-capture", a->orbit.beyond_capture,
                "orbit the full circle at the given elevation even where the capture never looked");
  cmd->add_option("--background", a->background, "linear RGB background, each 0..1 (default white)")
      ->expected(3);
  cmd->add_flag("--alpha", a->render.alpha, "transparent background (RGBA PNGs)");
  cmd->add_flag("--no-video", a->no_video, "skip the MP4");
  cmd->add_flag("--force", a->force, "overwrite existing outputs in the directory");
  cmd->add_flag("--json", a->json, "print the summary (render.json) on stdout");
  cmd->add_option("-o,--out", a->out, "output directory")->required();
  cmd->callback([a, &global] { run(*a, global); });
}

}  // namespace
LGN_REGISTER_COMMAND(60, add_render);
}  // namespace lorgnette::cli
