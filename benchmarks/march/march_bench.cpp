// Marcher benchmarks, writing CSV + PNG charts into --out:
//  table1.csv/.png          frame times at 854x480, 1280x720, 1920x1080, head alone and + glasses
//  early_termination.csv    march time and samples with glasses / without (the paper: 2-4 % faster)
//  quality.csv/.png         frame time against PSNR to a reference render (step 1/4 of the model's)
//                           for coarser steps and for lower resolutions upsampled bilinearly
// The head is a trained model (--model) or, without one, the analytic head stand-in.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <opencv2/imgproc.hpp>

#include "fit/placement_transform.h"
#include "host/dataset/metrics.h"
#include "host/render/analytic_field.h"
#include "host/render/frame_bench.h"
#include "host/render/render_job.h"
#include "host/render/renderer.h"
#include "host/util/chart.h"
#include "mesh/frame_surfaces.h"
#include "mesh/glasses.h"
#include "mesh/placed_glasses.h"
#include "mesh/surface_pass.h"

using namespace lorgnette;
using namespace lorgnette::render;

namespace {
struct Args {
  std::string model, glasses = std::string(LORGNETTE_DATA_DIR) + "/glasses/glasses-06/scene.gltf",
                     out = "bench-march";
  std::string quality_size = "640x360", sizes;
  uint32_t repeats = 3;
  bool skip_table = false, skip_quality = false;
};

// Upsamples (bilinear) a rendered RGB image to w x h for comparison with the reference.
Image resize_to(const Image& img, int w, int h) {
  cv::Mat src(img.height, img.width, CV_32FC(img.channels), const_cast<float*>(img.pixels.data()));
  cv::Mat dst;
  cv::resize(src, dst, cv::Size(w, h), 0, 0, cv::INTER_LINEAR);
  Image out(w, h, img.channels);
  std::memcpy(out.pixels.data(), dst.ptr<float>(), out.pixels.size() * sizeof(float));
  return out;
}

Image rgb_of(const RenderResult& r) { return to_output_image(r.rgba, false); }

void write_table1(const Args& a, const nlohmann::json& rows) {
  std::vector<std::vector<std::string>> csv;
  ChartSeries head{"head", {}, {}}, glasses{"head + glasses", {}, {}};
  for (const auto& r : rows) {
    csv.push_back({r["device"], r["scene"], r["resolution"], r["glasses"].get<bool>() ? "yes" : "no",
                   fmt::format("{:.2f}", r["median_ms"].get<double>()),
                   fmt::format("{:.2f}", r["march_ms"].get<double>()),
                   fmt::format("{:.2f}", r["surface_ms"].get<double>()),
                   fmt::format("{:.3f}", r["samples_per_ray"].get<double>()),
                   std::to_string(r["samples_evaluated"].get<uint64_t>())});
    auto size = parse_size(r["resolution"]);
    (r["glasses"].get<bool>() ? glasses : head).x.push_back(size[1]);
    (r["glasses"].get<bool>() ? glasses : head).y.push_back(r["median_ms"].get<double>());
  }
  write_csv(a.out + "/table1.csv",
            {"device", "scene", "resolution", "glasses", "median_ms", "march_ms", "surface_ms",
             "samples_per_ray", "samples_evaluated"},
            csv);
  write_chart(a.out + "/table1.png", {"Frame time (Table 1 replica)", "image height (px, 16:9)", "ms"},
              {head, glasses});
  // Early termination: compare the march alone (the surface pass is extra work on the CPU here).
  std::vector<std::vector<std::string>> et;
  for (size_t i = 0; i + 1 < rows.size(); i += 2) {
    const auto &h = rows[i], &g = rows[i + 1];
    et.push_back({h["resolution"], fmt::format("{:.2f}", h["march_ms"].get<double>()),
                  fmt::format("{:.2f}", g["march_ms"].get<double>()),
                  fmt::format("{:.4f}", g["march_ms"].get<double>() / h["march_ms"].get<double>()),
                  fmt::format("{:.4f}", double(g["samples_evaluated"].get<uint64_t>()) /
                                            double(h["samples_evaluated"].get<uint64_t>()))});
  }
  write_csv(a.out + "/early_termination.csv",
            {"resolution", "march_ms_head", "march_ms_glasses", "time_ratio", "samples_ratio"}, et);
}

using RenderFn =
    std::function<RenderResult(const Camera&, const lorgnette::SurfaceBuffers*, const RenderOptions&)>;

double timed_median(const std::function<void()>& f, int n) {
  std::vector<double> ms;
  for (int i = 0; i < n; ++i) {
    auto t0 = std::chrono::steady_clock::now();
    f();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  return median(ms);
}

// Frame time against PSNR to a reference (step x 1/4): coarser steps, and lower resolutions.
void quality_vs_time(const Args& a, const std::function<Camera(uint32_t, uint32_t)>& camera,
                     const RenderFn& render) {
  auto size = parse_size(a.quality_size);
  Camera cam = camera(size[0], size[1]);
  RenderOptions ref_opts;
  ref_opts.step_scale = 0.25f;
  Image ref = rgb_of(render(cam, nullptr, ref_opts));
  write_image(a.out + "/quality_reference.png", ref);
  std::vector<std::vector<std::string>> csv;
  ChartSeries steps{"step scale (full resolution)", {}, {}},
      res{"resolution scale (step 1, bilinear up)", {}, {}};
  for (float step : {0.5f, 1.0f, 1.5f, 2.0f, 3.0f, 4.0f}) {
    RenderOptions o;
    o.step_scale = step;
    RenderResult r;
    double ms = timed_median([&] { r = render(cam, nullptr, o); }, 2);
    double p = dataset::psnr(rgb_of(r), ref);
    csv.push_back({"step", fmt::format("{}", step), fmt::format("{:.2f}", ms), fmt::format("{:.2f}", p),
                   fmt::format("{:.2f}", r.samples_per_ray())});
    steps.x.push_back(ms);
    steps.y.push_back(p);
  }
  for (float scale : {1.0f, 0.75f, 0.5f, 0.35f}) {
    Camera small = camera(uint32_t(size[0] * scale + 0.5f), uint32_t(size[1] * scale + 0.5f));
    RenderResult r;
    double ms = timed_median([&] { r = render(small, nullptr, {}); }, 2);
    double p = dataset::psnr(resize_to(rgb_of(r), ref.width, ref.height), ref);
    csv.push_back({"resolution", fmt::format("{}", scale), fmt::format("{:.2f}", ms),
                   fmt::format("{:.2f}", p), fmt::format("{:.2f}", r.samples_per_ray())});
    res.x.push_back(ms);
    res.y.push_back(p);
  }
  write_csv(a.out + "/quality.csv", {"setting", "value", "frame_ms", "psnr_db", "samples_per_ray"}, csv);
  write_chart(a.out + "/quality.png",
              {fmt::format("Frame time vs quality at {} (reference: step x 0.25)", a.quality_size),
               "frame ms", "PSNR dB"},
              {steps, res});
}
}  // namespace

int main(int argc, char** argv) {
  Args a;
  CLI::App app{"march benchmarks: Table 1, early termination, time vs quality"};
  app.add_option("--model", a.model, "trained model (.lnerf); default: the analytic head");
  app.add_option("--glasses", a.glasses, "glasses frame")->capture_default_str();
  app.add_option("--out", a.out, "output directory")->capture_default_str();
  app.add_option("--repeats", a.repeats, "timed frames per Table 1 row")->capture_default_str();
  app.add_option("--quality-size", a.quality_size, "size of the quality study")->capture_default_str();
  app.add_option("--sizes", a.sizes,
                 "Table 1 sizes, comma-separated WxH (default 854x480,1280x720,1920x1080)");
  app.add_flag("--skip-quality", a.skip_quality, "only Table 1");
  app.add_flag("--skip-table", a.skip_table, "only the quality study");
  CLI11_PARSE(app, argc, argv);
  try {
    std::filesystem::create_directories(a.out);
    cl::Runtime rt;
    VolumeScene scene;
    std::unique_ptr<AnalyticHeadScene> analytic;
    Marcher marcher(rt);
    RenderFn render;
    std::unique_ptr<nerf::NerfModel> model;
    Renderer renderer(rt);
    if (!a.model.empty()) {
      model = std::make_unique<nerf::NerfModel>(nerf::NerfModel::load(rt, a.model));
      scene.aabb_min = model->aabb().min;
      scene.aabb_max = model->aabb().max;
      render = [&](const Camera& c, const lorgnette::SurfaceBuffers* s, const RenderOptions& o) {
        return renderer.render(*model, c, s, o);
      };
    } else {
      analytic = std::make_unique<AnalyticHeadScene>(rt);
      scene = analytic->scene();
      render = [&](const Camera& c, const lorgnette::SurfaceBuffers* s, const RenderOptions& o) {
        return marcher.render(scene, c, s, o);
      };
    }
    auto camera = [&](uint32_t w, uint32_t h) {
      OrbitSpec o;
      for (int i = 0; i < 3; ++i) {
        o.center[i] = 0.5f * (scene.aabb_min[i] + scene.aabb_max[i]);
        o.half_extent[i] = 0.5f * (scene.aabb_max[i] - scene.aabb_min[i]);
      }
      o.width = w;
      o.height = h;
      return orbit_cameras(o)[0];
    };
    if (!a.skip_table) {
      FrameBenchSpec spec;
      spec.repeats = a.repeats;
      spec.device = rt.device().name;
      spec.scene = a.model.empty() ? "analytic head" : a.model;
      spec.camera = camera;
      if (!a.sizes.empty()) {
        spec.sizes.clear();
        for (const auto& sz : CLI::detail::split(a.sizes, ',')) spec.sizes.push_back(parse_size(sz));
      }
      mesh::Glasses g = mesh::load_glasses(a.glasses);
      auto v = [](const std::array<float, 3>& a) { return Eigen::Vector3d(a[0], a[1], a[2]); };
      fit::Transform p = fit::rough_placement(g.metrics.total_width_mm, v(scene.aabb_min), v(scene.aabb_max));
      std::shared_ptr<const mesh::SurfacePass> pass = mesh::place_glasses_mesh(std::move(g), p, {}).pass;
      GlassesSurfaces glasses = mesh::frame_surfaces(pass);
      spec.glasses = &glasses;
      FrameOptions sequential;  // this table times the march and the surface pass one after the other
      sequential.concurrent = false;
      spec.variants = {{"sequential", sequential}};
      auto rows =
          run_frame_bench(spec, [&](const Camera& c, const GlassesSurfaces* g, const FrameOptions& o) {
            return model ? renderer.render_frame(*model, c, g, o)
                         : render_hybrid_frame(marcher, scene, c, g, o);
          });
      write_table1(a, rows);
      // One try-on image of the 720p view for the record.
      Camera c = camera(1280, 720);
      lorgnette::SurfaceBuffers sb = pass->render(c, mesh::SurfaceParams{});
      write_image(a.out + "/tryon_720p.png", rgb_of(render(c, &sb, RenderOptions{})));
      std::cout << rows.dump(2) << "\n";
    }
    if (!a.skip_quality) quality_vs_time(a, camera, render);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
