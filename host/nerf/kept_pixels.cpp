// Kept training pixels as runs; see kept_pixels.h.
#include "host/nerf/kept_pixels.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lorgnette::nerf {
namespace {

// Adds the spans of one polygon to `rows`: for the centre line of each row it crosses, the crossings
// of its edges, sorted, pair up into inside intervals; pixel x is inside when x0 <= x + 0.5 < x1.
void add_polygon_spans(const IgnorePolygon& poly, int width, int height,
                       std::vector<std::vector<std::pair<int, int>>>& rows) {
  float y_min = poly[0].y(), y_max = poly[0].y();
  for (const auto& v : poly) y_min = std::min(y_min, v.y()), y_max = std::max(y_max, v.y());
  const int r0 = std::max(0, int(std::floor(y_min))), r1 = std::min(height - 1, int(std::ceil(y_max)));
  std::vector<float> xs;
  for (int y = r0; y <= r1; ++y) {
    const float yc = float(y) + 0.5f;
    xs.clear();
    for (size_t i = 0; i < poly.size(); ++i) {
      const Eigen::Vector2f& a = poly[i];
      const Eigen::Vector2f& b = poly[(i + 1) % poly.size()];
      if ((a.y() <= yc) == (b.y() <= yc)) continue;
      xs.push_back(a.x() + (yc - a.y()) * (b.x() - a.x()) / (b.y() - a.y()));
    }
    std::sort(xs.begin(), xs.end());
    for (size_t k = 0; k + 1 < xs.size(); k += 2) {
      const int begin = std::max(0, int(std::ceil(xs[k] - 0.5f)));
      const int end = std::min(width, int(std::ceil(xs[k + 1] - 0.5f)));
      if (begin < end) rows[size_t(y)].push_back({begin, end});
    }
  }
}

// Sorts and merges overlapping or touching spans.
void merge_spans(std::vector<std::pair<int, int>>& spans) {
  std::sort(spans.begin(), spans.end());
  std::vector<std::pair<int, int>> out;
  for (const auto& s : spans) {
    if (!out.empty() && s.first <= out.back().second)
      out.back().second = std::max(out.back().second, s.second);
    else
      out.push_back(s);
  }
  spans = std::move(out);
}

}  // namespace

std::vector<std::vector<std::pair<int, int>>> ignored_spans(const std::vector<IgnorePolygon>& polygons,
                                                            int width, int height) {
  std::vector<std::vector<std::pair<int, int>>> rows(size_t(std::max(height, 0)));
  for (const IgnorePolygon& poly : polygons)
    if (poly.size() >= 3) add_polygon_spans(poly, width, height, rows);
  for (auto& spans : rows) merge_spans(spans);
  return rows;
}

KeptPixels kept_pixel_runs(const std::vector<std::pair<int, int>>& sizes,
                           const std::vector<const std::vector<IgnorePolygon>*>& ignore) {
  KeptPixels k;
  uint64_t base = 0, run_start = 0;     // global index of the view's first pixel; of the open kept run
  auto close_run = [&](uint64_t end) {  // the kept pixels [run_start, end) become a run
    if (end <= run_start) return;
    k.runs.push_back(uint32_t(k.kept));
    k.runs.push_back(uint32_t(run_start));
    k.kept += end - run_start;
  };
  for (size_t v = 0; v < sizes.size(); ++v) {
    const auto [w, h] = sizes[v];
    if (v < ignore.size() && ignore[v] && !ignore[v]->empty()) {
      const auto rows = ignored_spans(*ignore[v], w, h);
      for (int y = 0; y < h; ++y)
        for (const auto& [x0, x1] : rows[size_t(y)]) {
          close_run(base + uint64_t(y) * w + uint64_t(x0));
          run_start = base + uint64_t(y) * w + uint64_t(x1);
          k.ignored += uint64_t(x1 - x0);
        }
    }
    base += uint64_t(w) * uint64_t(h);
  }
  close_run(base);
  if (k.kept == 0)
    throw std::runtime_error(fmt::format(
        "every one of the {} training pixels lies in an ignore region: nothing is left to train on; check "
        "the dataset's ignore_regions.json (or delete it)",
        base));
  if (k.ignored == 0) k.runs.clear();  // one run of everything: the sampler needs no table
  return k;
}

}  // namespace lorgnette::nerf
