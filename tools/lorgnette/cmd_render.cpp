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

#include "fit/placement_json.h"
#include "fit/placement_transform.h"
#include "host/dataset/dataset.h"
#include "host/nerf/model.h"
#include "host/render/render_job.h"
#include "host/render/renderer.h"
#include "host/render/view_plan.h"
#include "mesh/placed_glasses.h"
#include "tools/lorgnette/command.h"

namespace lorgnette::cli {
namespace {

struct RenderArgs {
  std::string model, glasses, placement, transform, pose, size = "854x480", out, marcher = "auto";
  std::vector<float> translate, rotate, background, front;
  float scale = 1.0f, fov = 30.0f, elevation = 0.0f, step_scale = 1.0f;
  uint32_t orbit = 0, spp = 1, surface_spp = 4;
  bool alpha = false, force = false, json = false, no_video = false, beyond_capture = false;
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

void run(const RenderArgs& a, GlobalOptions& global) {
  if ((a.orbit > 0) == !a.pose.empty()) throw std::runtime_error("give either --orbit N or --pose JSON");
  if (!a.front.empty()) {
    if (a.orbit == 0)
      throw std::runtime_error(
          "--front says where an --orbit starts: give --orbit N too (a --pose camera is placed by its own "
          "transform_matrix)");
    render::check_orbit_front(vec3(a.front, {}));
  }
  auto size = render::parse_size(a.size);
  {
    // Refuse outputs the user already has before any work (device, model, glasses).
    render::RenderJob planned;
    planned.video = !a.no_video;
    planned.cameras.resize(a.orbit > 0 ? a.orbit : 1);
    render::check_outputs_free(a.out, render::render_job_outputs(planned), a.force);
  }
  cl::Runtime rt(global.runtime());
  nerf::NerfModel model = nerf::NerfModel::load(rt, a.model);

  render::RenderJob job;
  job.out_dir = a.out;
  job.force = a.force;
  job.video = !a.no_video;
  job.options.spp = a.spp;
  job.options.alpha = a.alpha;
  job.options.step_scale = a.step_scale;
  job.options.marcher = render::parse_marcher_kind(a.marcher);
  if (!a.background.empty()) job.options.background = vec3(a.background, {1, 1, 1});
  std::string range_source;
  std::optional<nerf::ViewRange> range = render::model_view_range(model, &range_source);
  if (range) spdlog::info("captured directions: {} from {}", range->summary(), range_source);
  if (a.orbit > 0) {
    render::OrbitSpec base = render::model_orbit(model, {});
    base.fov_y_deg = a.fov;
    base.width = size[0];
    base.height = size[1];
    render::OrbitRequest req;
    req.views = a.orbit;
    req.elevation_deg = a.elevation;
    if (!a.front.empty()) req.front = vec3(a.front, base.front);
    req.beyond_capture = a.beyond_capture;
    render::OrbitPlan plan = render::plan_orbit(base, range, req);
    for (const auto& note : plan.notes) spdlog::info("orbit: {}", note);
    job.cameras = render::orbit_cameras(plan.spec);
  } else {
    job.cameras = {render::read_pose(a.pose, size[0], size[1], a.fov)};
    if (std::string note = render::pose_outside_note(job.cameras[0], range); !note.empty())
      spdlog::warn("{}", note);
  }

  std::string glasses_path = a.glasses;
  mesh::TempleBend temples;
  fit::Transform placement = glasses_transform(a, glasses_path, temples);
  std::unique_ptr<mesh::SurfacePass> pass;
  if (!glasses_path.empty()) {
    pass = mesh::load_placed_glasses(glasses_path, placement, temples).pass;
    mesh::SurfaceParams sp;
    sp.samples_per_pixel = int(a.surface_spp);
    job.surfaces = [&pass, sp](const Camera& cam) { return pass->render(cam, sp); };
  } else if (!a.placement.empty() || !a.transform.empty()) {
    throw std::runtime_error("a placement was given but no glasses: add --glasses FRAME");
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
  cmd->add_option("--orbit", a->orbit,
                  "N views around the head, starting at its front, within the directions the capture saw "
                  "(plus a margin)");
  cmd->add_option("--pose", a->pose, "one camera: JSON with transform_matrix (+ fl_x, w, h or fov_y_deg)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--size", a->size, "image size WIDTHxHEIGHT")->capture_default_str();
  cmd->add_option("--spp", a->spp, "NeRF rays per pixel")->capture_default_str()->check(CLI::Range(1, 64));
  cmd->add_option("--surface-spp", a->surface_spp, "glasses samples per pixel (anti-aliasing)")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
  cmd->add_option("--step-scale", a->step_scale, "marching step multiplier (>1 faster, coarser)")
      ->capture_default_str()
      ->check(CLI::Range(0.25f, 8.0f));
  cmd->add_option("--marcher", a->marcher, "auto (fused on a GPU, wavefront on a CPU), wavefront or fused")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "wavefront", "fused"}));
  cmd->add_option("--fov", a->fov, "vertical field of view, degrees")
      ->capture_default_str()
      ->check(CLI::Range(5.0f, 120.0f));
  cmd->add_option("--elevation", a->elevation, "orbit elevation, degrees")
      ->capture_default_str()
      ->check(CLI::Range(-80.0f, 80.0f));
  cmd->add_option(
         "--front", a->front,
         "the first view's direction from the head (default: the capture's mean camera); its tilt adds "
         "to --elevation; clamped into the captured directions unless --beyond-capture")
      ->expected(3);
  cmd->add_flag("--beyond-capture", a->beyond_capture,
                "orbit the full circle at the given elevation even where the capture never looked");
  cmd->add_option("--background", a->background, "linear RGB background (default white)")->expected(3);
  cmd->add_flag("--alpha", a->alpha, "transparent background (RGBA PNGs)");
  cmd->add_flag("--no-video", a->no_video, "skip the MP4");
  cmd->add_flag("--force", a->force, "overwrite existing outputs in the directory");
  cmd->add_flag("--json", a->json, "print the summary (render.json) on stdout");
  cmd->add_option("-o,--out", a->out, "output directory")->required();
  cmd->callback([a, &global] { run(*a, global); });
}

}  // namespace
LGN_REGISTER_COMMAND(60, add_render);
}  // namespace lorgnette::cli
