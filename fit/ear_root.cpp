// The ear rests found on the head's density (see ear_root.h).
#include "fit/ear_root.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace lorgnette::fit {
namespace {

constexpr double kMiss = -std::numeric_limits<double>::infinity();

struct Crease {
  bool found = false;
  double lateral_mm = 0.0, height_mm = 0.0, bend_deg = 0.0;
  double top_mm = 0.0;  // the ear's top `span` outside the crease
};

// A depth's profile (heights along d_eye, inside to outside) bends from the skull's steep side onto
// the ear's flatter top at the crease: the point where the slope over `span` steps outside it is
// most above the slope inside it (as angles), by at least min_bend_deg, with the inside falling at
// least as steeply as max_inner_slope_deg, the outside within outer_slope_deg and the crease within
// the height band. Both sides must be hits.
Crease crease_of(const std::vector<double>& h, const std::vector<double>& lateral, int span,
                 const EarRootOptions& o) {
  const int n = int(h.size());
  Crease c;
  for (int j = span; j + span < n; ++j) {
    if (h[j - span] == kMiss || h[j] == kMiss || h[j + span] == kMiss) continue;
    if (h[j] < o.lowest_mm || h[j] > o.highest_mm) continue;
    const double run = lateral[j + span] - lateral[j];
    const double in = std::atan((h[j] - h[j - span]) / run) * 180.0 / M_PI,
                 out = std::atan((h[j + span] - h[j]) / run) * 180.0 / M_PI;
    if (in > o.max_inner_slope_deg || out < o.outer_slope_deg[0] || out > o.outer_slope_deg[1]) continue;
    const double bend = out - in;
    if (bend >= o.min_bend_deg && (!c.found || bend > c.bend_deg))
      c = {true, lateral[j], h[j], bend, h[j + span]};
  }
  return c;
}

void check(const EarRootInputs& in, const EarRootOptions& o) {
  if (!(in.mm_per_unit > 0.0)) throw std::invalid_argument("find_ear_root: mm_per_unit must be positive");
  if (in.side != 1 && in.side != -1) throw std::invalid_argument("find_ear_root: side must be +1 or -1");
  for (double s : {o.depth_step_mm, o.lateral_step_mm, o.ray_step_mm})
    if (!(s > 0.0)) throw std::invalid_argument("find_ear_root: steps must be positive");
  if (!(o.back_mm + o.front_mm > 0.0 && o.inward_mm + o.outward_mm > 0.0 && o.above_mm + o.below_mm > 0.0))
    throw std::invalid_argument("find_ear_root: the search window is empty");
  if (!(o.opacity > 0.0 && o.opacity < 1.0))
    throw std::invalid_argument("find_ear_root: opacity must lie in (0, 1)");
}

std::vector<double> grid(double from, double to, double step) {
  std::vector<double> v;
  for (int i = 0; from + i * step <= to + 1e-9; ++i) v.push_back(from + i * step);
  return v;
}

}  // namespace

namespace {

// The field of vertical rays cast down beside the head at `depths` (mm along d_fwd from the temple),
// each at `laterals` (mm outwards along the side's d_eye): per depth, each ray's height (mm above
// the eye corner) where its opacity from above reaches the options' level, or kMiss. One density
// query for all the rays.
std::vector<std::vector<double>> ray_heights(const DensityFn& density_of, const EarRootInputs& in,
                                             const EarRootOptions& o, const std::vector<double>& depths,
                                             const std::vector<double>& laterals) {
  const double mpu = in.mm_per_unit;
  const Eigen::Vector3d out = in.side * in.d_eye.normalized(), up = in.d_up.normalized(),
                        fwd = in.d_fwd.normalized();
  const double eye_height = (in.eye_corner - in.temple).dot(up) * mpu;               // mm above the temple
  const std::vector<double> heights = grid(-o.below_mm, o.above_mm, o.ray_step_mm);  // from the eyes
  const size_t per_ray = heights.size();
  std::vector<Eigen::Vector3f> pts;
  pts.reserve(depths.size() * laterals.size() * per_ray);
  for (double f : depths)
    for (double x : laterals)
      for (size_t k = per_ray; k-- > 0;)  // from the top down
        pts.push_back((in.temple + (x * out + f * fwd + (eye_height + heights[k]) * up) / mpu).cast<float>());
  const std::vector<float> density = density_of(pts);
  if (density.size() != pts.size())
    throw std::runtime_error("find_ear_root: the density returned the wrong number of values");

  const double target = -std::log(1.0 - o.opacity), dt = o.ray_step_mm / mpu;
  std::vector<std::vector<double>> hits(depths.size(), std::vector<double>(laterals.size(), kMiss));
  size_t at = 0;
  for (size_t i = 0; i < depths.size(); ++i)
    for (size_t j = 0; j < laterals.size(); ++j, at += per_ray) {
      double tau = 0.0;
      for (size_t k = 1; k < per_ray; ++k) {
        const double add = 0.5 * (double(density[at + k - 1]) + double(density[at + k])) * dt;
        if (tau + add >= target) {
          const double frac = (target - tau) / add;  // within the step from sample k-1 (above) to k
          hits[i][j] = heights[per_ray - k] - frac * o.ray_step_mm;
          break;
        }
        tau += add;
      }
    }
  return hits;
}

}  // namespace

std::vector<EarRootProfile> ear_root_profiles(const DensityFn& density, const EarRootInputs& in,
                                              const EarRootOptions& o, const std::vector<double>& depths_mm) {
  check(in, o);
  const std::vector<double> laterals = grid(-o.inward_mm, o.outward_mm, o.lateral_step_mm);
  const std::vector<std::vector<double>> hits = ray_heights(density, in, o, depths_mm, laterals);
  std::vector<EarRootProfile> profiles;
  for (size_t i = 0; i < depths_mm.size(); ++i) {
    EarRootProfile p;
    p.depth_mm = depths_mm[i], p.lateral_mm = laterals;
    for (double h : hits[i]) p.height_mm.push_back(h == kMiss ? std::nan("") : h);
    profiles.push_back(std::move(p));
  }
  return profiles;
}

std::vector<EarRootSide> find_ear_root_lines(const DensityFn& density_of, const EarRootInputs& in,
                                             const EarRootOptions& o) {
  check(in, o);
  const double mpu = in.mm_per_unit;
  const Eigen::Vector3d out = in.side * in.d_eye.normalized(), up = in.d_up.normalized(),
                        fwd = in.d_fwd.normalized();
  const double eye_height = (in.eye_corner - in.temple).dot(up) * mpu;  // mm above the temple
  const std::vector<double> depths = grid(-o.back_mm, o.front_mm, o.depth_step_mm),
                            laterals = grid(-o.inward_mm, o.outward_mm, o.lateral_step_mm);
  const int span = std::max(1, int(std::lround(o.bend_span_mm / o.lateral_step_mm)));

  // Each ray's height (mm above the eye corners) where its opacity from above reaches the level.
  const std::vector<std::vector<double>> hits = ray_heights(density_of, in, o, depths, laterals);
  std::vector<Crease> creases(depths.size());
  for (size_t i = 0; i < depths.size(); ++i) {
    const std::vector<double>& profile = hits[i];
    creases[i] = crease_of(profile, laterals, span, o);
    if (spdlog::should_log(spdlog::level::trace))  // (the message is formatted before the call)
      spdlog::trace("fit: {} side, {:+.0f} mm from the temple: {}", in.side > 0 ? "left" : "right", depths[i],
                    creases[i].found
                        ? fmt::format("a crease {:.1f} mm out, {:+.1f} mm high, {:.0f} deg",
                                      creases[i].lateral_mm, creases[i].height_mm, creases[i].bend_deg)
                        : "no crease");
  }

  // Runs of consecutive depths whose creases continue each other. Along a run, each crease's height
  // is the median of it and its neighbours (a NeRF's heights scatter by a millimetre or two from
  // depth to depth). The rest lies on the run (of at least min_slices) that rises highest: a temple
  // arm lowered onto the ear comes to rest on the highest support.
  struct Run {
    int start = 0, len = 0;
    std::vector<double> smooth;
    double top = kMiss;
  };
  std::vector<Run> runs;
  int found_any = 0, longest = 0;
  for (int i = 0, n = int(depths.size()); i < n;) {
    if (!creases[i].found) {
      ++i;
      continue;
    }
    int j = i + 1;
    while (j < n && creases[j].found &&
           std::abs(creases[j].lateral_mm - creases[j - 1].lateral_mm) <= o.max_step_mm &&
           std::abs(creases[j].height_mm - creases[j - 1].height_mm) <= o.max_step_mm)
      ++j;
    found_any += j - i, longest = std::max(longest, j - i);
    Run run{i, j - i, {}, kMiss};
    for (int k = 0; k < run.len; ++k) {
      // The three nearest depths of the run (at its ends, the end and the two inside it: a median of
      // two would take the higher).
      const int from = std::clamp(k - 1, 0, std::max(0, run.len - 3)), to = std::min(run.len - 1, from + 2);
      std::vector<double> near;
      for (int m = from; m <= to; ++m) near.push_back(creases[i + m].height_mm);
      std::sort(near.begin(), near.end());
      run.smooth.push_back(near[near.size() / 2]);
      run.top = std::max(run.top, run.smooth.back());
    }
    if (run.len >= std::max(1, o.min_slices)) runs.push_back(std::move(run));
    i = j;
  }
  if (runs.empty()) {
    EarRootSide r;
    r.slices = longest;
    r.why = found_any == 0
                ? fmt::format(
                      "no crease between skull and ear in {} depths (hair over the ear, or the capture "
                      "did not see it)",
                      depths.size())
                : fmt::format("creases in only {} consecutive depths of {} (need {})", longest, depths.size(),
                              o.min_slices);
    return {r};
  }
  std::stable_sort(runs.begin(), runs.end(), [](const Run& a, const Run& b) { return a.top > b.top; });
  // Lines shorter than short_line_slices above the highest line at least that long go after it: a
  // temple slides under hair's edge onto the ear's root.
  auto long_line =
      std::find_if(runs.begin(), runs.end(), [&](const Run& r) { return r.len >= o.short_line_slices; });
  if (long_line != runs.end()) std::rotate(runs.begin(), long_line, long_line + 1);
  std::vector<EarRootSide> found;
  for (const Run& run : runs) {
    EarRootSide r;
    r.slices = run.len;
    r.back_mm = depths[run.start], r.front_mm = depths[run.start + run.len - 1];
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();    // lateral, height, depth (mm)
    Eigen::Vector2d where = Eigen::Vector2d::Zero();  // lateral, depth (mm), weighted
    double weights = 0.0;
    for (int k = 0; k < run.len; ++k) {
      const int i = run.start + k;
      const double w = run.smooth[k] - (run.top - o.depth_window_mm);
      if (o.depth_window_mm > 0.0 && w > 0.0)
        where += w * Eigen::Vector2d(creases[i].lateral_mm, depths[i]), weights += w;
      if (run.smooth[k] >= run.top - o.plateau_mm) {
        sum += Eigen::Vector3d(creases[i].lateral_mm, creases[i].height_mm, depths[i]);
        r.ear_top.push_back(in.temple + ((creases[i].lateral_mm + o.bend_span_mm) * out + depths[i] * fwd +
                                         (eye_height + creases[i].top_mm) * up) /
                                            mpu);
        r.bend_deg = std::max(r.bend_deg, creases[i].bend_deg);
        ++r.plateau;
      }
    }
    Eigen::Vector3d c = sum / r.plateau;
    if (weights > 0.0) c.x() = where.x() / weights, c.z() = where.y() / weights;
    if (o.rest_behind_front_mm >= 0.0) c.z() = std::max(r.back_mm, r.front_mm - o.rest_behind_front_mm);
    r.found = true;
    r.height_mm = c.y(), r.depth_mm = c.z(), r.lateral_mm = c.x();
    r.point = in.temple + (c.x() * out + c.z() * fwd + (eye_height + c.y()) * up) / mpu;
    found.push_back(std::move(r));
  }
  return found;
}

EarRootSide find_ear_root(const DensityFn& density, const EarRootInputs& in, const EarRootOptions& options) {
  return find_ear_root_lines(density, in, options).front();
}

std::string EarRoots::summary() const {
  auto say = [](const char* name, const EarRootSide& s) {
    return s.found
               ? fmt::format(
                     "{} ear's root found (a {:.0f} deg crease over {} depths, {} at its top; {:+.1f} mm "
                     "above the eye corner, {:+.1f} mm forward of the temple{}{})",
                     name, s.bend_deg, s.slices, s.plateau, s.height_mm, s.depth_mm,
                     s.higher_vetoed > 0 ? fmt::format("; under {} higher line(s) vetoed", s.higher_vetoed)
                                         : "",
                     s.passed_over > 0 ? fmt::format("; under {} higher line(s) passed over", s.passed_over)
                                       : "")
               : fmt::format("{} ear's root not found: {}", name, s.why);
  };
  const char* used = use == Use::kBoth       ? "both ears from the density"
                     : use == Use::kMirrored ? "one ear from the density, mirrored onto the other side"
                                             : "the ears from Eq. 2-3";
  return fmt::format("{}; {}; {}{}", say("left", left), say("right", right), note.empty() ? "" : note + "; ",
                     used);
}

EarRoots apply_ear_roots(const DensityFn& density, const EarInputs& in, const Eigen::Vector3d& d_eye,
                         double mm_per_unit, const EarRootOptions& options, EarPoints& ears,
                         const EarVeto& accept) {
  EarRoots r;
  // Each side's lines of creases that the veto accepts, highest first (hair over the top of the ear
  // makes a higher line at the hair's edge, above the ear's own); or, when there is none, the side
  // not found and why.
  auto side = [&](const Eigen::Vector3d& t, const Eigen::Vector3d& e, int sign) {
    std::vector<EarRootSide> lines =
        find_ear_root_lines(density, {t, e, d_eye, in.d_up, in.d_fwd, sign, mm_per_unit}, options);
    for (const EarRootSide& line : lines)
      if (line.found)
        spdlog::debug(
            "fit: {} side's line of creases: {:+.1f} mm above the eye corner, {:+.1f} mm forward of the "
            "temple, {} depths ({:+.0f}..{:+.0f} mm), {:.0f} deg",
            sign > 0 ? "left" : "right", line.height_mm, line.depth_mm, line.slices, line.back_mm,
            line.front_mm, line.bend_deg);
    if (!lines.front().found) return lines;
    std::vector<EarRootSide> accepted;
    std::string first_veto, next_veto;
    int vetoed = 0;
    for (EarRootSide& line : lines) {
      std::string veto = accept ? accept(line) : std::string();
      // Under hair (or under a higher line) a line must lie where ears do: hair's own lower edges make
      // creases too.
      if (veto.empty() && &line != lines.data() && line.height_mm > options.plausible_highest_mm)
        veto = fmt::format(
            "it lies under hair and {:.1f} mm above the eye corner, over the {:.0f} allowed there",
            line.height_mm, options.plausible_highest_mm);
      if (veto.empty()) {
        line.higher_vetoed = vetoed;
        accepted.push_back(line);
        continue;
      }
      ++vetoed;
      if (first_veto.empty())
        first_veto =
            fmt::format("{} (a crease {:+.1f} mm above the eye corner, {:+.1f} mm forward of the temple)",
                        veto, line.height_mm, line.depth_mm);
      else if (next_veto.empty())
        next_veto = veto;
    }
    if (!accepted.empty()) return accepted;
    EarRootSide s = lines.front();
    s.found = false, s.vetoed = true;
    s.why = lines.size() == 1 ? first_veto
                              : fmt::format("{}; and the {} lower line(s) of creases too (the highest: {})",
                                            first_veto, lines.size() - 1, next_veto);
    return std::vector<EarRootSide>{s};
  };
  const std::vector<EarRootSide> lefts = side(in.t_l, in.e_l, +1), rights = side(in.t_r, in.e_r, -1);
  r.left = lefts.front(), r.right = rights.front();
  const Eigen::Vector3d up = in.d_up.normalized(), fwd = in.d_fwd.normalized();
  // Two rests' difference in height and in depth (mm, along d_up and d_fwd; the temples are no
  // reference: their errors are what this search avoids).
  auto gaps = [&](const EarRootSide& a, const EarRootSide& b) {
    const Eigen::Vector3d d = (a.point - b.point) * mm_per_unit;
    return Eigen::Vector2d(std::abs(d.dot(up)), std::abs(d.dot(fwd)));
  };
  auto agree = [&](const Eigen::Vector2d& gap) {
    return gap.x() <= options.max_height_gap_mm && gap.y() <= options.max_depth_gap_mm;
  };
  const bool both = r.left.found && r.right.found;
  const Eigen::Vector2d first = both ? gaps(r.left, r.right) : Eigen::Vector2d::Zero();
  if (both)
    spdlog::debug("fit: the two sides' first lines lie {:.1f} mm apart in height and {:.1f} mm in depth",
                  first.x(), first.y());
  if (both && !agree(first)) {
    // A head's ears lie at one height and depth: a lower pair of lines that agrees is likelier the two
    // roots than the first lines, one of which lies elsewhere (hair's edge, the ear's back).
    // A line that takes its side's first's place must be as well founded as a line that goes first
    // (short_line_slices depths): short lines lie at the window's back edge, or on hair's edge.
    auto may_stand_in = [&](const EarRootSide& line, size_t place) {
      return place == 0 || line.slices >= options.short_line_slices;
    };
    // The agreeing pair ranked highest together (the least sum of places), then the closest in depth.
    size_t best_l = 0, best_r = 0, best_rank = 0;
    double best_depth_gap = 0.0;
    for (size_t i = 0; i < lefts.size(); ++i)
      for (size_t j = 0; j < rights.size(); ++j) {
        const Eigen::Vector2d gap = gaps(lefts[i], rights[j]);
        if (!agree(gap) || !may_stand_in(lefts[i], i) || !may_stand_in(rights[j], j)) continue;
        if (best_rank == 0 || i + j < best_rank || (i + j == best_rank && gap.y() < best_depth_gap))
          best_l = i, best_r = j, best_rank = i + j, best_depth_gap = gap.y();
      }
    if (best_rank > 0) {  // (0 + 0, the first pair, does not agree)
      r.note = fmt::format(
          "the first lines lay {:.1f} mm apart in height and {:.1f} mm in depth; the left side's line {} and "
          "the right side's line {}, which agree, were used",
          first.x(), first.y(), best_l + 1, best_r + 1);
      r.left = lefts[best_l], r.right = rights[best_r];
      r.left.passed_over = int(best_l), r.right.passed_over = int(best_r);
    }
  }
  if (r.left.found && r.right.found) {
    // A head's ears lie at one height (the ears' heights set the frame's pitch).
    const double gap = gaps(r.left, r.right).x();
    if (gap > options.max_height_gap_mm) {
      const std::string why = fmt::format(
          "the two sides' rests lie {:.1f} mm apart in height (over {:.0f}; left {:+.1f} mm above its eye "
          "corner, right {:+.1f})",
          gap, options.max_height_gap_mm, r.left.height_mm, r.right.height_mm);
      r.left.found = r.right.found = false;
      r.left.why = r.right.why = why;
    }
  }
  // Each rest moved to `height_and_depth`'s height and depth (along d_up, d_fwd), at its own width.
  auto level = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& height_and_depth) -> Eigen::Vector3d {
    return p + (height_and_depth - p).dot(up) * up + (height_and_depth - p).dot(fwd) * fwd;
  };
  if (r.left.found && r.right.found) {
    // One height and depth for both, the mean of the two: a difference within the limit is the
    // search's scatter along the flat top of the root more than the head's asymmetry, and it would
    // yaw or roll the frame away from the face's own axes.
    Eigen::Vector3d mid = 0.5 * (r.left.point + r.right.point);
    // A line over fewer than short_line_slices depths, opposite one at least that long, is a fragment
    // of its root: its front end is not where the root leaves the head, so the depth is the long
    // line's alone (the height stays the mean: the fragment lies on the root's top).
    const bool short_l = r.left.slices < options.short_line_slices,
               short_r = r.right.slices < options.short_line_slices;
    if (short_l != short_r) {
      const EarRootSide& whole = short_l ? r.right : r.left;
      mid += (whole.point - mid).dot(fwd) * fwd;
      r.note += fmt::format("{}the {} side's line holds {} depths: the rests' depth is the {} side's",
                            r.note.empty() ? "" : "; ", short_l ? "left" : "right",
                            (short_l ? r.left : r.right).slices, short_l ? "right" : "left");
    }
    ears.f_l = level(r.left.point, mid), ears.f_r = level(r.right.point, mid);
    r.use = EarRoots::Use::kBoth;
    return r;
  }
  const EarRootSide* lone = r.left.found ? &r.left : r.right.found ? &r.right : nullptr;
  // Opposite a side vetoed as hair too: the found side passed the same veto, so it is not that hair,
  // and an ear at the height where ears lie is nearer the truth than Eq. 2-3's point (20-40 mm off).
  if (lone && lone->height_mm <= options.plausible_highest_mm) {
    const bool left = lone == &r.left;
    const Eigen::Vector3d out_other = (left ? -1.0 : 1.0) * d_eye.normalized();
    const Eigen::Vector3d beside = (left ? in.t_r : in.t_l) + lone->lateral_mm * out_other / mm_per_unit;
    (left ? ears.f_l : ears.f_r) = lone->point;
    (left ? ears.f_r : ears.f_l) = level(beside, lone->point);
    r.use = EarRoots::Use::kMirrored;
  } else if (lone) {
    r.note = fmt::format(
        "the found one lies {:.1f} mm above its eye corner, over the {:.0f} allowed for one side alone",
        lone->height_mm, options.plausible_highest_mm);
  }
  return r;
}

}  // namespace lorgnette::fit
