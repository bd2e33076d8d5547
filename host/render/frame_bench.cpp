// Table 1 frame-time measurement: see frame_bench.h.
#include "host/render/frame_bench.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <map>
#include <stdexcept>

#include "host/util/chart.h"

namespace lorgnette::render {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

namespace {
// Per-frame times of one row, in milliseconds.
struct RowTimes {
  std::vector<double> total, march, surface, wait, upload, readback;
  RenderResult last;
  void add(const RenderResult& r) {
    total.push_back(r.seconds * 1e3);
    march.push_back(r.times.march * 1e3);
    surface.push_back(r.times.surface * 1e3);
    wait.push_back(r.times.surface_wait * 1e3);
    upload.push_back(r.times.upload * 1e3);
    readback.push_back(r.times.readback * 1e3);
  }
};

nlohmann::json make_row(const FrameBenchSpec& spec, const std::array<uint32_t, 2>& size, bool glasses,
                        const FrameVariant& v, const RowTimes& t) {
  const double total = median(t.total);
  const FrameOptions& o = v.options;
  nlohmann::json row = {
      {"device", spec.device},
      {"scene", spec.scene},
      {"resolution", fmt::format("{}x{}", size[0], size[1])},
      {"pixels", uint64_t(size[0]) * size[1]},
      {"glasses", glasses},
      {"variant", v.name},
      {"marcher", t.last.fused ? "fused" : "wavefront"},
      {"concurrent", glasses && o.concurrent},
      {"surface_spp", glasses ? o.surface_spp : 0},
      {"wave_min", o.march.wave_min},
      {"wave_max", o.march.wave_max},
      {"median_ms", total},
      {"march_ms", median(t.march)},
      {"surface_ms", median(t.surface)},
      {"surface_wait_ms", median(t.wait)},
      {"upload_ms", median(t.upload)},
      {"readback_ms", median(t.readback)},
      {"samples_per_ray", t.last.samples_per_ray()},
      {"samples_evaluated", t.last.samples_evaluated},
      {"samples_per_second", total > 0 ? double(t.last.samples_evaluated) / (total * 1e-3) : 0.0},
      {"composited_per_second", total > 0 ? double(t.last.samples_composited) / (total * 1e-3) : 0.0},
      {"waves", t.last.waves},
      {"frames", spec.repeats}};
  row["transfer_ms"] = row["upload_ms"].get<double>() + row["readback_ms"].get<double>();
  spdlog::info(
      "{} {} {} [{}]: {:.1f} ms (march {:.1f}, surface {:.1f}, waited {:.1f}, transfer {:.1f}), "
      "{:.2f} samples/ray, {:.2f} M samples/s",
      spec.device, row["resolution"].get<std::string>(), glasses ? "head+glasses" : "head", v.name, total,
      median(t.march), median(t.surface), median(t.wait), row["transfer_ms"].get<double>(),
      t.last.samples_per_ray(), row["samples_per_second"].get<double>() * 1e-6);
  return row;
}
}  // namespace

nlohmann::json run_frame_bench(const FrameBenchSpec& spec, const FrameRenderer& render) {
  if (!spec.camera) throw std::invalid_argument("frame bench: no camera");
  if (spec.repeats == 0) throw std::invalid_argument("frame bench: repeats must be >= 1");
  if (spec.variants.empty()) throw std::invalid_argument("frame bench: no frame settings to time");
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& size : spec.sizes) {
    Camera cam = spec.camera(size[0], size[1]);
    for (int glasses = 0; glasses < (spec.glasses ? 2 : 1); ++glasses) {
      const GlassesSurfaces* g = glasses ? spec.glasses : nullptr;
      // Without glasses the variants differ only in their march settings: time each distinct one.
      std::vector<const FrameVariant*> variants;
      for (const auto& v : spec.variants) {
        bool same = false;
        for (const auto* w : variants)
          same |= !glasses && w->options.march.marcher == v.options.march.marcher &&
                  w->options.march.wave_min == v.options.march.wave_min &&
                  w->options.march.wave_max == v.options.march.wave_max;
        if (!same) variants.push_back(&v);
      }
      std::vector<RowTimes> times(variants.size());
      for (uint32_t k = 0; k <= spec.repeats; ++k)  // k == 0 is the warm-up frame
        for (size_t i = 0; i < variants.size(); ++i) {
          RenderResult r = render(cam, g, variants[i]->options);
          if (k == 0) continue;
          times[i].add(r);
          times[i].last = std::move(r);
        }
      for (size_t i = 0; i < variants.size(); ++i)
        rows.push_back(make_row(spec, size, bool(glasses), *variants[i], times[i]));
    }
  }
  return rows;
}

namespace {
const char* const kCsvFields[] = {"device",
                                  "scene",
                                  "resolution",
                                  "pixels",
                                  "glasses",
                                  "variant",
                                  "marcher",
                                  "concurrent",
                                  "surface_spp",
                                  "wave_min",
                                  "wave_max",
                                  "median_ms",
                                  "march_ms",
                                  "surface_ms",
                                  "surface_wait_ms",
                                  "upload_ms",
                                  "readback_ms",
                                  "transfer_ms",
                                  "samples_per_ray",
                                  "samples_evaluated",
                                  "samples_per_second",
                                  "composited_per_second",
                                  "waves",
                                  "frames"};

std::string csv_value(const nlohmann::json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_boolean()) return v.get<bool>() ? "1" : "0";
  if (v.is_number_float()) return fmt::format("{:.6g}", v.get<double>());
  return v.dump();
}
}  // namespace

void write_frame_bench_csv(const nlohmann::json& rows, const std::string& path) {
  std::vector<std::string> header(std::begin(kCsvFields), std::end(kCsvFields));
  std::vector<std::vector<std::string>> lines;
  for (const auto& r : rows) {
    std::vector<std::string> line;
    for (const auto& f : header) line.push_back(r.contains(f) ? csv_value(r[f]) : "");
    lines.push_back(std::move(line));
  }
  write_csv(path, header, lines);
}

void write_frame_bench_chart(const nlohmann::json& rows, const std::string& title, const std::string& path) {
  std::map<std::string, ChartSeries> series;
  for (const auto& r : rows) {
    std::string name = fmt::format("{} {} ({})", r["glasses"].get<bool>() ? "head + glasses" : "head alone",
                                   r["variant"].get<std::string>(), r.value("marcher", "?"));
    ChartSeries& s = series[name];
    s.name = name;
    s.x.push_back(double(r["pixels"].get<uint64_t>()) * 1e-6);
    s.y.push_back(r["median_ms"].get<double>());
  }
  std::vector<ChartSeries> list;
  for (auto& [name, s] : series) list.push_back(std::move(s));
  write_chart(path, {title, "megapixels per frame (480p, 720p, 1080p)", "frame time, ms (median)"}, list);
}

}  // namespace lorgnette::render
