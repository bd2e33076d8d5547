// Surface pass benchmark: wall time of SurfacePass::render at 854x480, 1280x720 and 1920x1080 with
// 1, 4 and 16 samples per pixel on 2 threads, for the heaviest shared frame (glasses-01, the
// 2.8 MB glTF, 76k triangles) and a parametric frame, placed in metres as on a head and seen from
// 0.45 m ("selfie": the whole head in view, the frame covers ~2.5 % of the pixels) and from 0.2 m
// ("close-up": the frame fills most of the width, ~20 % of the pixels covered). Writes
// surface_pass.csv and surface_pass.png into the output directory (argument 1, default ".").
// Each configuration runs twice; the faster run is reported (the machine is shared).
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include "host/util/chart.h"
#include "mesh/glasses.h"
#include "mesh/parametric.h"
#include "mesh/surface_pass.h"

using namespace lorgnette;
using namespace lorgnette::mesh;

int main(int argc, char** argv) {
  std::string out = argc > 1 ? argv[1] : ".";
  int threads = argc > 2 ? std::atoi(argv[2]) : 2;
  std::filesystem::create_directories(out);
  Eigen::Matrix4f place = Eigen::Matrix4f::Identity();
  place.topLeftCorner<3, 3>() *= 0.001f;  // canonical mm -> metres
  struct Frame {
    std::string name;
    TriMesh mesh;
  };
  std::vector<Frame> frames;
  frames.push_back({"glasses-01 (76k tris)",
                    load_glasses(std::string(LORGNETTE_DATA_DIR) + "/glasses/glasses-01/scene.gltf").mesh});
  frames.push_back({"parametric rect 52-18-140", make_parametric_frame({}).mesh});
  const std::pair<int, int> sizes[] = {{854, 480}, {1280, 720}, {1920, 1080}};
  std::vector<std::vector<std::string>> rows;
  std::vector<ChartSeries> series;
  for (const auto& f : frames) {
    SurfacePass pass(f.mesh, place);
    std::fprintf(stderr, "%s: %zu triangles\n", f.name.c_str(), f.mesh.triangle_count());
    for (const char* framing : {"selfie", "close-up"})
      for (int spp : {1, 4, 16}) {
        bool close = std::string(framing) == "close-up";
        ChartSeries s{fmt::format("{}, {}, {} spp", f.name, framing, spp), {}, {}, false};
        for (auto [w, h] : sizes) {
          Camera cam = close ? look_at_camera({0.06f, 0.03f, 0.16f}, {0, 0, -0.04f}, {0, 1, 0}, 40.0f, w, h)
                             : look_at_camera({0.12f, 0.04f, 0.42f}, {0, 0, -0.04f}, {0, 1, 0}, 40.0f, w, h);
          SurfaceParams p;
          p.samples_per_pixel = spp;
          p.threads = threads;
          double best = 1e30, coverage = 0;
          for (int rep = 0; rep < 2; ++rep) {
            auto t0 = std::chrono::steady_clock::now();
            SurfaceBuffers b = pass.render(cam, p);
            best =
                std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
            coverage = 0;
            for (size_t i = 0; i < b.pixel_count(); ++i) coverage += b.color_alpha[4 * i + 3] > 0;
            coverage /= b.pixel_count();
          }
          double msps = static_cast<double>(w) * h * spp / best / 1e6;
          std::fprintf(stderr,
                       "  %s %dx%d %2d spp: %8.1f ms (%.2f M primary samples/s, %.1f %% pixels covered)\n",
                       framing, w, h, spp, best * 1e3, msps, coverage * 100);
          rows.push_back({f.name, framing, std::to_string(w), std::to_string(h), std::to_string(spp),
                          std::to_string(threads), fmt::format("{:.2f}", best * 1e3),
                          fmt::format("{:.3f}", msps), fmt::format("{:.4f}", coverage)});
          s.x.push_back(static_cast<double>(w) * h / 1e6);
          s.y.push_back(best * 1e3);
        }
        series.push_back(s);
      }
  }
  write_csv(
      out + "/surface_pass.csv",
      {"frame", "framing", "width", "height", "spp", "threads", "ms", "msamples_per_s", "covered_fraction"},
      rows);
  write_chart(out + "/surface_pass.png",
              {"Surface pass time (Embree 3, 2 threads)", "megapixels", "milliseconds", false, 900, 560},
              series);
  std::fprintf(stderr, "wrote %s/surface_pass.csv and .png\n", out.c_str());
  return 0;
}
