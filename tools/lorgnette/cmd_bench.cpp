// `lorgnette bench frames [--json] [--model M] [--glasses F [--placement P]] [--out DIR] [--compare]`:
// the paper's Table 1 (frame times at 480p/720p/1080p, head alone and head + glasses, samples per ray
// and per second, the frame's split between march, surface pass and transfers) on every OpenCL
// device found, with a CSV and a chart per device under --out. --compare times the sequential frame
// and the pre-#16 pipeline beside the default, frame by frame in turn; --marcher auto,wavefront
// times the fused and the wavefront marcher side by side the same way. Without --model an analytic
// head stands in (and the rows say so). Logic lives in host/render/frame_bench.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <Eigen/Core>
#include <cctype>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "fit/placement_json.h"
#include "fit/placement_transform.h"
#include "host/cl/device.h"
#include "host/nerf/model.h"
#include "host/render/analytic_field.h"
#include "host/render/frame_bench.h"
#include "host/render/render_job.h"
#include "host/render/renderer.h"
#include "host/render/view_plan.h"
#include "host/util/bounds.h"
#include "mesh/frame_surfaces.h"
#include "mesh/placed_glasses.h"
#include "tools/lorgnette/command.h"

namespace lorgnette::cli {
namespace {

struct BenchArgs {
  std::string model, glasses, placement, sizes, marcher = "auto", out;
  int repeats = 3, surface_spp = 4;  // signed, so -1 is refused with the range
  std::vector<int> waves;            // --waves MIN,MAX for the default variant
  float step_scale = 1.0f;
  bool json = false, compare = false, force = false;
};

// Every number against host/util/bounds.h (and the sizes parsed) before any device is opened.
void validate(const BenchArgs& a) {
  check_bound(bounds::kBenchRepeats, a.repeats);
  check_bound(bounds::kSurfaceSpp, a.surface_spp);
  check_bound(bounds::kStepScale, a.step_scale);
  for (int w : a.waves) check_bound(bounds::kWaves, w);
  if (a.waves.size() == 2 && a.waves[0] > a.waves[1])
    throw std::runtime_error(fmt::format("--waves MIN,MAX: MIN {} is above MAX {}", a.waves[0], a.waves[1]));
  for (const auto& s : CLI::detail::split(a.sizes, ','))
    if (!s.empty()) render::parse_size(s);
}

// The frame settings timed, per marcher named in --marcher (a comma list: "auto,wavefront" times
// both, frame by frame in turn): the defaults, and with --compare the same frame sequential (surface
// pass, then march) and the pipeline before #16 (sequential, waves of 4..64 segments per ray).
std::vector<render::FrameVariant> frame_variants(const BenchArgs& a) {
  std::vector<render::FrameVariant> v;
  for (const auto& word : CLI::detail::split(a.marcher, ',')) {
    render::FrameOptions o;
    o.march.step_scale = a.step_scale;
    o.march.marcher = render::parse_marcher_kind(word);
    o.surface_spp = uint32_t(a.surface_spp);
    if (a.waves.size() == 2) o.march.wave_min = uint32_t(a.waves[0]), o.march.wave_max = uint32_t(a.waves[1]);
    v.push_back({"default", o});
    if (a.compare) {
      o.concurrent = false;
      v.push_back({"sequential", o});
      o.march.wave_min = 4;
      o.march.wave_max = 64;
      v.push_back({"baseline", o});
    }
  }
  return v;
}

// "pthread-skylake-avx512-Intel(R) Xeon(R) Processor" -> "pthread-skylake-avx512-intel-r-xeon-r".
std::string file_slug(const std::string& name) {
  std::string s;
  for (char c : name) {
    bool keep = std::isalnum(static_cast<unsigned char>(c));
    if (keep)
      s += char(std::tolower(static_cast<unsigned char>(c)));
    else if (!s.empty() && s.back() != '-')
      s += '-';
  }
  if (s.size() > 40) s.resize(s.rfind('-', 40) != std::string::npos ? s.rfind('-', 40) : 40);
  while (!s.empty() && s.back() == '-') s.pop_back();
  return s.empty() ? "device" : s;
}

nlohmann::json bench_device(const BenchArgs& a, const cl::DeviceInfo& dev, GlobalOptions& global) {
  cl::RuntimeOptions ro = global.runtime();
  ro.device = std::to_string(dev.index);
  cl::Runtime rt(ro);
  std::unique_ptr<nerf::NerfModel> model;
  std::unique_ptr<render::AnalyticHeadScene> analytic;
  render::VolumeScene scene;
  if (!a.model.empty()) {
    model = std::make_unique<nerf::NerfModel>(nerf::NerfModel::load(rt, a.model));
    scene.aabb_min = model->aabb().min;
    scene.aabb_max = model->aabb().max;
  } else {
    analytic = std::make_unique<render::AnalyticHeadScene>(rt);
    scene = analytic->scene();
  }
  render::FrameBenchSpec spec;
  spec.repeats = uint32_t(a.repeats);
  spec.device = dev.name;
  spec.scene = a.model.empty() ? "analytic head" : a.model;
  if (!a.sizes.empty()) {
    spec.sizes.clear();
    for (const auto& s : CLI::detail::split(a.sizes, ',')) spec.sizes.push_back(render::parse_size(s));
  }
  // A trained head is timed from the capture's mean direction (inside what the capture saw,
  // view_plan.h); the analytic head from +z.
  std::optional<nerf::ViewRange> range;
  if (model) range = render::model_view_range(*model);
  spec.camera = [&](uint32_t w, uint32_t h) {
    render::OrbitSpec o;
    for (int i = 0; i < 3; ++i) {
      o.center[i] = 0.5f * (scene.aabb_min[i] + scene.aabb_max[i]);
      o.half_extent[i] = 0.5f * (scene.aabb_max[i] - scene.aabb_min[i]);
    }
    o.width = w;
    o.height = h;
    return render::orbit_cameras(render::plan_orbit(o, range, {}).spec)[0];
  };
  render::GlassesSurfaces glasses;  // the callbacks own the surface pass
  if (!a.glasses.empty()) {
    mesh::Glasses g = mesh::load_glasses(a.glasses);
    auto v = [](const std::array<float, 3>& a) { return Eigen::Vector3d(a[0], a[1], a[2]); };
    fit::Transform p = fit::rough_placement(g.metrics.total_width_mm, v(scene.aabb_min), v(scene.aabb_max));
    mesh::TempleBend temples;
    if (!a.placement.empty()) {
      fit::PlacementFile pf = fit::read_placement(a.placement);
      p = pf.transform;
      temples = pf.temples.bend;
    }
    glasses = mesh::frame_surfaces(mesh::place_glasses_mesh(std::move(g), p, temples).pass);
    spec.glasses = &glasses;
  }
  spec.variants = frame_variants(a);
  render::Renderer renderer(rt);
  render::Marcher marcher(rt);
  nlohmann::json rows = render::run_frame_bench(
      spec, [&](const Camera& cam, const render::GlassesSurfaces* g, const render::FrameOptions& o) {
        return model ? renderer.render_frame(*model, cam, g, o)
                     : render::render_hybrid_frame(marcher, scene, cam, g, o);
      });
  if (!a.out.empty()) {
    const std::string base = a.out + "/frames-" + file_slug(dev.name);
    render::write_frame_bench_csv(rows, base + ".csv");
    render::write_frame_bench_chart(rows, "Table 1 frame times: " + dev.name, base + ".png");
    spdlog::info("wrote {}.csv and {}.png", base, base);
  }
  return rows;
}

void add_frames(CLI::App& bench, GlobalOptions& global) {
  auto a = std::make_shared<BenchArgs>();
  auto* cmd =
      bench.add_subcommand("frames", "Table 1: frame times per resolution, head alone and with glasses");
  cmd->add_option("--model", a->model, "trained model (.lnerf); default: an analytic head")
      ->check(CLI::ExistingFile);
  cmd->add_option("--glasses", a->glasses, "glasses frame for the head + glasses rows")
      ->check(CLI::ExistingFile);
  cmd->add_option("--placement", a->placement, "placement.json (default: a rough automatic placement)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--repeats", a->repeats, "timed frames per row, after one warm-up")->capture_default_str();
  cmd->add_option("--sizes", a->sizes, "comma-separated WxH list (default 854x480,1280x720,1920x1080)");
  cmd->add_option("--surface-spp", a->surface_spp, "glasses samples per pixel")->capture_default_str();
  cmd->add_option("--step-scale", a->step_scale, "marching step multiplier")->capture_default_str();
  cmd->add_option(
         "--marcher", a->marcher,
         "auto (fused on a GPU, wavefront on a CPU), wavefront or fused; a comma list (auto,wavefront) "
         "times each, in turn")
      ->capture_default_str()
      ->check([](const std::string& list) {
        for (const auto& word : CLI::detail::split(list, ','))
          if (word != "auto" && word != "wavefront" && word != "fused")
            return "'" + word + "' is not a marcher: use auto, wavefront or fused (comma-separated)";
        return std::string();
      });
  cmd->add_flag("--json", a->json, "print the rows as one JSON array on stdout");
  cmd->add_option("--out", a->out, "directory for frames-<device>.csv and .png (one pair per device)");
  cmd->add_flag("--compare", a->compare,
                "also time the sequential frame and the pre-#16 pipeline (sequential, waves 4..64), in turn");
  cmd->add_flag("--force", a->force, "overwrite the CSV and chart in --out");
  cmd->add_option("--waves", a->waves,
                  "MIN,MAX segments per ray and wave of the wavefront march (default 2,8; tuning)")
      ->delimiter(',')
      ->expected(2);
  cmd->callback([a, &global] {
    validate(*a);
    std::vector<cl::DeviceInfo> devices;
    for (const auto& dev : cl::list_devices())
      if (global.device.empty() || cl::select_device(global.device).index == dev.index)
        devices.push_back(dev);
    if (!a->out.empty()) {
      std::filesystem::create_directories(a->out);
      std::vector<std::string> names;
      for (const auto& dev : devices)
        for (const char* ext : {".csv", ".png"}) names.push_back("frames-" + file_slug(dev.name) + ext);
      std::vector<std::string> taken;
      for (const auto& n : names)
        if (std::filesystem::exists(std::filesystem::path(a->out) / n)) taken.push_back(n);
      if (!taken.empty() && !a->force)
        throw std::runtime_error(
            fmt::format("'{}' already holds {}: choose another --out directory or pass --force to overwrite",
                        a->out, fmt::join(taken, ", ")));
    }
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& dev : devices)
      for (auto& r : bench_device(*a, dev, global)) rows.push_back(r);
    if (a->json) {
      std::cout << rows.dump(2) << "\n";
      return;
    }
    std::cout << fmt::format("{:<28} {:>10} {:>7} {:>10} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>11} {:>9}\n",
                             "device", "resolution", "glasses", "variant", "marcher", "frame_ms", "march_ms",
                             "surf_ms", "wait_ms", "xfer_ms", "samples/ray", "Msamp/s");
    for (const auto& r : rows)
      std::cout << fmt::format(
          "{:<28} {:>10} {:>7} {:>10} {:>9} {:>9.1f} {:>9.1f} {:>9.1f} {:>9.1f} {:>9.1f} {:>11.2f} "
          "{:>9.2f}\n",
          r["device"].get<std::string>().substr(0, 28), r["resolution"].get<std::string>(),
          r["glasses"].get<bool>() ? "yes" : "no", r["variant"].get<std::string>(),
          r["marcher"].get<std::string>(), r["median_ms"].get<double>(), r["march_ms"].get<double>(),
          r["surface_ms"].get<double>(), r["surface_wait_ms"].get<double>(), r["transfer_ms"].get<double>(),
          r["samples_per_ray"].get<double>(), r["samples_per_second"].get<double>() * 1e-6);
  });
}

void add_bench(CLI::App& app, GlobalOptions& global) {
  CLI::App* bench = nullptr;
  try {
    bench = app.get_subcommand("bench");  // another module may have created it
  } catch (const CLI::OptionNotFound&) {
    bench = app.add_subcommand("bench", "benchmarks (frames: the paper's Table 1)");
    bench->require_subcommand(1);
  }
  add_frames(*bench, global);
}

}  // namespace
LGN_REGISTER_COMMAND(90, add_bench);
}  // namespace lorgnette::cli
