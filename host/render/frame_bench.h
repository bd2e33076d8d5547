// The paper's Table 1 as a reusable measurement: frame times at 854x480, 1280x720 and 1920x1080
// (16:9), head alone and head + glasses, median over repeated frames after a warm-up frame, with
// samples per ray and per second and the frame's split between march, surface pass and transfers.
// Several frame settings (variants, e.g. this code's defaults against an older configuration) are
// timed side by side, frame by frame in turn, so a shared machine's load falls on all of them alike.
// The renderer and the glasses come in as callbacks, so the same code times the NeRF head, the
// analytic stand-in, and any device.
#pragma once
#include <array>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "host/render/hybrid_frame.h"
#include "host/render/marcher.h"

namespace lorgnette::render {

struct FrameVariant {
  std::string name;
  FrameOptions options;
};

struct FrameBenchSpec {
  std::vector<std::array<uint32_t, 2>> sizes{{854, 480}, {1280, 720}, {1920, 1080}};
  uint32_t repeats = 3;  // timed frames per row (after one warm-up frame)
  std::string device;    // written into every row
  std::string scene;     // e.g. the model path or "analytic"
  // Camera for a size: the head from the front, framed.
  std::function<Camera(uint32_t width, uint32_t height)> camera;
  const GlassesSurfaces* glasses = nullptr;  // nullptr: rows for the head alone only
  std::vector<FrameVariant> variants{{"default", FrameOptions{}}};
};

using FrameRenderer = std::function<RenderResult(const Camera&, const GlassesSurfaces*, const FrameOptions&)>;

// One JSON row per (size, glasses, variant): device, scene, resolution, glasses, variant, marcher
// (the kernels that marched it: fused or wavefront), concurrent, surface_spp, wave_min, wave_max, median_ms
// (the whole frame), and the medians of its parts march_ms, surface_ms (the surface pass's own time,
// overlapped when concurrent), surface_wait_ms (the march idle for it), upload_ms, readback_ms, transfer_ms
// (their sum); samples_per_ray, samples_evaluated, samples_per_second (evaluated / median frame time),
// composited_per_second (the samples the image used, per second), waves (of the wavefront march;
// each costs kernel launches and two read-backs), frames.
nlohmann::json run_frame_bench(const FrameBenchSpec& spec, const FrameRenderer& render);

// The rows as CSV (one line per row, the fields above) and a chart of frame time against pixels
// per frame, one series per variant and glasses.
void write_frame_bench_csv(const nlohmann::json& rows, const std::string& path);
void write_frame_bench_chart(const nlohmann::json& rows, const std::string& title, const std::string& path);

double median(std::vector<double> v);

}  // namespace lorgnette::render
