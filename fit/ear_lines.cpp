// The ear search's line finder (see ear_lines.h).
#include "fit/ear_lines.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lorgnette::fit {

namespace {

double slope_deg(const std::vector<double>& h, const std::vector<double>& lateral, int from, int to) {
  return std::atan((h[to] - h[from]) / (lateral[to] - lateral[from])) * 180.0 / M_PI;
}

// The ear's top outside a crease at sample j: from `span` samples out, outwards while each step keeps
// an ear top's slope, at most `span` samples further.
std::vector<Eigen::Vector2d> ear_top_of(const std::vector<double>& h, const std::vector<double>& lateral,
                                        int j, int span, const EarCreaseOptions& o) {
  std::vector<Eigen::Vector2d> top{{lateral[j + span], h[j + span]}};
  for (int k = j + span + 1; k < int(h.size()) && k <= j + 2 * span && !std::isnan(h[k]); ++k) {
    const double step = slope_deg(h, lateral, k - 1, k);
    if (step < o.outer_slope_deg[0] || step > o.outer_slope_deg[1]) break;
    top.emplace_back(lateral[k], h[k]);
  }
  return top;
}

}  // namespace

EarCrease find_crease(const std::vector<double>& h, const std::vector<double>& lateral, int span,
                      const EarCreaseOptions& o) {
  const int n = int(h.size());
  EarCrease c;
  int at = -1;
  for (int j = span; j + span < n; ++j) {
    if (std::isnan(h[j - span]) || std::isnan(h[j]) || std::isnan(h[j + span])) continue;
    if (h[j] < o.lowest_mm || h[j] > o.highest_mm) continue;
    const double in = slope_deg(h, lateral, j - span, j), out = slope_deg(h, lateral, j, j + span);
    if (in > o.max_inner_slope_deg || out < o.outer_slope_deg[0] || out > o.outer_slope_deg[1]) continue;
    const double bend = out - in;
    if (bend >= o.min_bend_deg && (!c.found || bend > c.bend_deg))
      c = {true, lateral[j], h[j], bend, h[j + span], {}}, at = j;
  }
  if (c.found) c.top = ear_top_of(h, lateral, at, span, o);
  return c;
}

namespace {

// Whether crease b, at the next depth, continues crease a's line.
bool continues(const EarCrease& a, const EarCrease& b, double max_step_mm) {
  return b.found && std::abs(b.lateral_mm - a.lateral_mm) <= max_step_mm &&
         std::abs(b.height_mm - a.height_mm) <= max_step_mm;
}

// The median of each crease's height and its two nearest neighbours in the line (at its ends, the end
// and the two inside it: a median of two would take the higher).
void smooth_heights(EarCreaseLine& line, const std::vector<EarCrease>& creases) {
  line.top = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < line.len; ++k) {
    const int from = std::clamp(k - 1, 0, std::max(0, line.len - 3)), to = std::min(line.len - 1, from + 2);
    std::vector<double> near;
    for (int m = from; m <= to; ++m) near.push_back(creases[line.start + m].height_mm);
    std::sort(near.begin(), near.end());
    line.smooth.push_back(near[near.size() / 2]);
    line.top = std::max(line.top, line.smooth.back());
  }
}

}  // namespace

std::vector<EarCreaseLine> trace_crease_lines(const std::vector<EarCrease>& creases, double max_step_mm) {
  std::vector<EarCreaseLine> lines;
  for (int i = 0, n = int(creases.size()); i < n;) {
    if (!creases[i].found) {
      ++i;
      continue;
    }
    int j = i + 1;
    while (j < n && continues(creases[j - 1], creases[j], max_step_mm)) ++j;
    EarCreaseLine line;
    line.start = i, line.len = j - i;
    smooth_heights(line, creases);
    lines.push_back(std::move(line));
    i = j;
  }
  return lines;
}

void order_crease_lines(std::vector<EarCreaseLine>& lines, int short_line_slices) {
  std::stable_sort(lines.begin(), lines.end(),
                   [](const EarCreaseLine& a, const EarCreaseLine& b) { return a.top > b.top; });
  auto long_line = std::find_if(lines.begin(), lines.end(),
                                [&](const EarCreaseLine& l) { return l.len >= short_line_slices; });
  if (long_line != lines.end()) std::rotate(lines.begin(), long_line, long_line + 1);
}

EarRootSide rest_of_line(const EarCreaseLine& line, const std::vector<EarCrease>& creases,
                         const std::vector<double>& depths, const EarLineOptions& o,
                         const EarSideFrame& frame, double bend_span_mm) {
  EarRootSide r;
  r.slices = line.len;
  r.back_mm = depths[line.start], r.front_mm = depths[line.start + line.len - 1];
  double lateral_sum = 0.0, height_sum = 0.0;    // over the plateau
  double weighted_lateral = 0.0, weights = 0.0;  // over the top, weighted
  for (int k = 0; k < line.len; ++k) {
    const EarCrease& c = creases[line.start + k];
    const double depth = depths[line.start + k];
    const double w = line.smooth[k] - (line.top - o.depth_window_mm);
    if (o.depth_window_mm > 0.0 && w > 0.0) weighted_lateral += w * c.lateral_mm, weights += w;
    if (line.smooth[k] >= line.top - o.plateau_mm) {
      lateral_sum += c.lateral_mm, height_sum += c.height_mm;
      std::vector<Eigen::Vector3d>& top = r.ear_top.emplace_back();
      for (const Eigen::Vector2d& t : c.top) top.push_back(frame.point(t.x(), depth, t.y()));
      if (top.empty()) top.push_back(frame.point(c.lateral_mm + bend_span_mm, depth, c.top_mm));
      r.bend_deg = std::max(r.bend_deg, c.bend_deg);
      ++r.plateau;
    }
  }
  r.found = true;
  r.lateral_mm = weights > 0.0 ? weighted_lateral / weights : lateral_sum / r.plateau;
  r.height_mm = height_sum / r.plateau;
  r.depth_mm = std::max(r.back_mm, r.front_mm - o.rest_behind_front_mm);
  r.point = frame.point(r.lateral_mm, r.depth_mm, r.height_mm);
  return r;
}

}  // namespace lorgnette::fit
