// Table 1 frame-time measurement: see frame_bench.h.
#include "host/render/frame_bench.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace lorgnette::render {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

namespace {
double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

nlohmann::json run_frame_bench(const FrameBenchSpec& spec, const FrameRenderer& render) {
  if (!spec.camera) throw std::invalid_argument("frame bench: no camera");
  if (spec.repeats == 0) throw std::invalid_argument("frame bench: repeats must be >= 1");
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& size : spec.sizes) {
    Camera cam = spec.camera(size[0], size[1]);
    for (int glasses = 0; glasses < (spec.surfaces ? 2 : 1); ++glasses) {
      std::vector<double> total, march, surface;
      RenderResult last;
      for (uint32_t k = 0; k <= spec.repeats; ++k) {  // k == 0 is the warm-up frame
        auto t0 = std::chrono::steady_clock::now();
        lorgnette::SurfaceBuffers s;
        if (glasses) s = spec.surfaces(cam);
        double surface_ms = ms_since(t0);
        last = render(cam, glasses ? &s : nullptr);
        if (k == 0) continue;
        total.push_back(ms_since(t0));
        march.push_back(last.seconds * 1e3);
        surface.push_back(surface_ms);
      }
      nlohmann::json row = {{"device", spec.device},
                            {"scene", spec.scene},
                            {"resolution", fmt::format("{}x{}", size[0], size[1])},
                            {"glasses", bool(glasses)},
                            {"median_ms", median(total)},
                            {"march_ms", median(march)},
                            {"surface_ms", median(surface)},
                            {"samples_per_ray", last.samples_per_ray()},
                            {"samples_evaluated", last.samples_evaluated},
                            {"frames", spec.repeats}};
      spdlog::info("{} {} {}: {:.1f} ms (march {:.1f}, surface {:.1f}), {:.2f} samples/ray", spec.device,
                   row["resolution"].get<std::string>(), glasses ? "head+glasses" : "head", median(total),
                   median(march), median(surface), last.samples_per_ray());
      rows.push_back(row);
    }
  }
  return rows;
}

}  // namespace lorgnette::render
