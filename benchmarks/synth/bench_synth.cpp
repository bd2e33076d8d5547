// Benchmark of dataset synthesis: procedural head build time, render time per view against image
// size (Embree, 3x3 anti-aliasing samples + soft shadows), full per-view synthesis time including
// PNG/EXR writing, and dlib face detection on the procedural head across yaw. Writes CSV files and
// PNG charts into the output directory (default ./bench-synth).
//   bench_synth [OUT_DIR] [--quick]
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include "fit/landmarks_dlib.h"
#include "host/util/chart.h"
#include "mesh/embree_scene.h"
#include "synth/synthesize.h"

using namespace lorgnette;
namespace fs = std::filesystem;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void bench_render(const synth::Subject& head, const std::string& out, bool quick) {
  std::vector<std::vector<std::string>> rows;
  ChartSeries render{"render only", {}, {}}, full{"render + write PNG/EXR", {}, {}};
  mesh::EmbreeScene scene(head.mesh, head.mesh_to_dataset);
  std::vector<int> sizes = quick ? std::vector<int>{128, 256} : std::vector<int>{128, 256, 400, 512};
  for (int size : sizes) {
    synth::SynthOptions o;
    o.width = o.height = size;
    o.views = quick ? 2 : 4;
    o.force = true;
    auto views = synth::make_camera_rig(synth::rig_for(head, o));
    auto t0 = std::chrono::steady_clock::now();
    for (const auto& v : views)
      synth::render_view(scene, v.camera, o.lighting, {o.samples_per_axis, std::nullopt, 0});
    double per_view = seconds_since(t0) / views.size();
    synth::SynthReport r = synth::synthesize_dataset(head, out + "/dataset-" + std::to_string(size), o);
    double per_view_full = r.seconds / r.views;
    std::printf("%4dx%-4d render %.3f s/view, synthesis %.3f s/view\n", size, size, per_view, per_view_full);
    rows.push_back({std::to_string(size), std::to_string(o.samples_per_axis * o.samples_per_axis),
                    fmt::format("{:.4f}", per_view), fmt::format("{:.4f}", per_view_full)});
    render.x.push_back(double(size) * size / 1e3), render.y.push_back(per_view);
    full.x.push_back(double(size) * size / 1e3), full.y.push_back(per_view_full);
  }
  write_csv(out + "/synth_time_per_view.csv", {"size", "samples_per_pixel", "render_s", "synthesis_s"}, rows);
  write_chart(
      out + "/synth_time_per_view.png",
      {"Procedural head: synthesis time per view (9 spp, soft shadows)", "kilopixels", "seconds per view"},
      {render, full});
}

void bench_detection(const synth::Subject& head, const std::string& out) {
  fit::LandmarkDetector detector;
  mesh::EmbreeScene scene(head.mesh, head.mesh_to_dataset);
  synth::SynthOptions o;
  o.width = o.height = 256;
  std::vector<std::vector<std::string>> rows;
  ChartSeries found{"detected (1) / missed (0)", {}, {}, true}, score{"HOG score", {}, {}};
  for (int yaw = -60; yaw <= 60; yaw += 10) {
    Camera cam = synth::rig_camera(synth::rig_for(head, o), float(yaw), 5.0f);
    auto v = synth::render_view(scene, cam, o.lighting, {3, Eigen::Vector3f(0.45f, 0.45f, 0.45f), 0});
    fit::FaceDetection d = detector.detect(v.rgba);
    double err = 0;
    if (d.found)
      for (int i = 17; i < 68; ++i) {
        const auto& p = head.ibug68[i];
        float u, w;
        camera_project(&cam, lgn_vec3(p.x(), p.y(), p.z()), &u, &w);
        err += (d.points[i] - Eigen::Vector2d(u, w)).norm() / 51;
      }
    std::printf("yaw %+3d: %s score %.2f mean landmark error (17-67) %.2f px\n", yaw,
                d.found ? "found" : "MISSED", d.score, d.found ? err : -1.0);
    rows.push_back({std::to_string(yaw), d.found ? "1" : "0", fmt::format("{:.3f}", d.score),
                    d.found ? fmt::format("{:.2f}", err) : ""});
    found.x.push_back(yaw), found.y.push_back(d.found ? 1.0 : 0.0);
    score.x.push_back(yaw), score.y.push_back(d.score);
    write_image(out + fmt::format("/view_yaw{:+d}.png", yaw), v.rgba);
  }
  write_csv(out + "/dlib_detection_vs_yaw.csv", {"yaw_deg", "detected", "score", "mean_err_px_17_67"}, rows);
  write_chart(out + "/dlib_detection_vs_yaw.png", {"dlib on the procedural head (256x256)", "yaw (deg)", ""},
              {found, score});
}

}  // namespace

int main(int argc, char** argv) {
  std::string out = "bench-synth";
  bool quick = false;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--quick")
      quick = true;
    else
      out = a;
  }
  fs::create_directories(out);
  try {
    auto t0 = std::chrono::steady_clock::now();
    synth::Subject head = synth::procedural_subject(synth::random_head_params(0));
    double build = seconds_since(t0);
    std::printf("procedural head: %zu triangles, texture %dx%d, built in %.2f s\n",
                head.mesh.triangle_count(), head.mesh.textures[0].width, head.mesh.textures[0].height, build);
    write_csv(out + "/head_build.csv", {"triangles", "texture_width", "seconds"},
              {{std::to_string(head.mesh.triangle_count()), std::to_string(head.mesh.textures[0].width),
                fmt::format("{:.3f}", build)}});
    bench_render(head, out, quick);
    bench_detection(head, out);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
