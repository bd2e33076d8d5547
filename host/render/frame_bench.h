// The paper's Table 1 as a reusable measurement: frame times at 854x480, 1280x720 and 1920x1080
// (16:9), head alone and head + glasses, median over repeated frames after a warm-up frame, plus
// samples per ray. The renderer and the glasses' surface pass come in as callbacks, so the same
// code times the NeRF head, the analytic stand-in, and any device.
#pragma once
#include <array>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "host/render/marcher.h"
#include "host/render/render_job.h"

namespace lorgnette::render {

struct FrameBenchSpec {
  std::vector<std::array<uint32_t, 2>> sizes{{854, 480}, {1280, 720}, {1920, 1080}};
  uint32_t repeats = 3;  // timed frames per row (after one warm-up frame)
  std::string device;    // written into every row
  std::string scene;     // e.g. the model path or "analytic"
  // Camera for a size: the head from the front, framed.
  std::function<Camera(uint32_t width, uint32_t height)> camera;
  SurfacePass surfaces;  // empty: rows for the head alone only
};

using FrameRenderer = std::function<RenderResult(const Camera&, const lorgnette::SurfaceBuffers*)>;

// One JSON row per (size, glasses): device, resolution, glasses, median_ms (surface pass + march),
// march_ms, surface_ms (medians), samples_per_ray, samples_evaluated, frames.
nlohmann::json run_frame_bench(const FrameBenchSpec& spec, const FrameRenderer& render);

double median(std::vector<double> v);

}  // namespace lorgnette::render
