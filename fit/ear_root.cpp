// The ear rests found on the head's density (see ear_root.h).
#include "fit/ear_root.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

namespace lorgnette::fit {

std::vector<EarRootProfile> ear_root_profiles(const DensityFn& density, const EarRootInputs& in,
                                              const EarRootOptions& o, const std::vector<double>& depths_mm) {
  check_ear_search(in, o.rays);
  const EarRayField field = cast_ear_rays(density, in, o.rays, depths_mm);
  std::vector<EarRootProfile> profiles;
  for (size_t i = 0; i < depths_mm.size(); ++i)
    profiles.push_back({depths_mm[i], field.laterals, field.heights[i]});
  return profiles;
}

namespace {

// Each depth's crease in the field.
std::vector<EarCrease> creases_of(const EarRayField& field, int side, const EarRootOptions& o) {
  const int span = std::max(1, int(std::lround(o.crease.bend_span_mm / o.rays.lateral_step_mm)));
  std::vector<EarCrease> creases;
  for (size_t i = 0; i < field.depths.size(); ++i) {
    const EarCrease& c = creases.emplace_back(find_crease(field.heights[i], field.laterals, span, o.crease));
    if (spdlog::should_log(spdlog::level::trace))  // (the message is formatted before the call)
      spdlog::trace("fit: {} side, {:+.0f} mm from the temple: {}", side > 0 ? "left" : "right",
                    field.depths[i],
                    c.found ? fmt::format("a crease {:.1f} mm out, {:+.1f} mm high, {:.0f} deg", c.lateral_mm,
                                          c.height_mm, c.bend_deg)
                            : "no crease");
  }
  return creases;
}

// A side with no line long enough, saying what the window showed.
EarRootSide no_line(const std::vector<EarCreaseLine>& lines, size_t depths, int min_slices) {
  int found_any = 0, longest = 0;
  for (const EarCreaseLine& l : lines) found_any += l.len, longest = std::max(longest, l.len);
  EarRootSide r;
  r.slices = longest;
  r.why =
      found_any == 0
          ? fmt::format(
                "no crease between skull and ear in {} depths (hair over the ear, or the capture "
                "did not see it)",
                depths)
          : fmt::format("creases in only {} consecutive depths of {} (need {})", longest, depths, min_slices);
  return r;
}

}  // namespace

std::vector<EarRootSide> find_ear_root_lines(const DensityFn& density, const EarRootInputs& in,
                                             const EarRootOptions& o) {
  check_ear_search(in, o.rays);
  const EarRayOptions& rays = o.rays;
  const EarRayField field =
      cast_ear_rays(density, in, rays, ear_grid(-rays.back_mm, rays.front_mm, rays.depth_step_mm));
  const std::vector<EarCrease> creases = creases_of(field, in.side, o);
  std::vector<EarCreaseLine> lines = trace_crease_lines(creases, o.line.max_step_mm);
  const int min_slices = std::max(1, o.line.min_slices);
  if (std::none_of(lines.begin(), lines.end(), [&](const EarCreaseLine& l) { return l.len >= min_slices; }))
    return {no_line(lines, field.depths.size(), o.line.min_slices)};
  lines.erase(
      std::remove_if(lines.begin(), lines.end(), [&](const EarCreaseLine& l) { return l.len < min_slices; }),
      lines.end());
  order_crease_lines(lines, o.line.short_line_slices);
  const EarSideFrame frame(in);
  std::vector<EarRootSide> found;
  for (const EarCreaseLine& line : lines)
    found.push_back(rest_of_line(line, creases, field.depths, o.line, frame, o.crease.bend_span_mm));
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

namespace {

// One side's lines that the veto accepts (rule 1), each found line logged.
std::vector<EarRootSide> side_lines(const DensityFn& density, const EarRootInputs& in,
                                    const EarRootOptions& o, const EarVeto& accept) {
  std::vector<EarRootSide> lines = find_ear_root_lines(density, in, o);
  for (const EarRootSide& line : lines)
    if (line.found)
      spdlog::debug(
          "fit: {} side's line of creases: {:+.1f} mm above the eye corner, {:+.1f} mm forward of the "
          "temple, {} depths ({:+.0f}..{:+.0f} mm), {:.0f} deg",
          in.side > 0 ? "left" : "right", line.height_mm, line.depth_mm, line.slices, line.back_mm,
          line.front_mm, line.bend_deg);
  return accepted_lines(std::move(lines), accept, o.pair);
}

// Rule 2: where both first lines are found but lie apart, a lower pair that agrees, if there is one.
void use_agreeing_pair(EarRoots& r, const std::vector<EarRootSide>& lefts,
                       const std::vector<EarRootSide>& rights, const EarPairFrame& frame,
                       const EarRootOptions& o) {
  if (!r.left.found || !r.right.found) return;
  const Eigen::Vector2d first = frame.gaps(r.left, r.right);
  spdlog::debug("fit: the two sides' first lines lie {:.1f} mm apart in height and {:.1f} mm in depth",
                first.x(), first.y());
  if (frame.agree(first, o.pair)) return;
  const std::optional<EarLinePair> pair =
      agreeing_pair(lefts, rights, frame, o.pair, o.line.short_line_slices);
  if (!pair) return;
  r.note = fmt::format(
      "the first lines lay {:.1f} mm apart in height and {:.1f} mm in depth; the left side's line {} and the "
      "right side's line {}, which agree, were used",
      first.x(), first.y(), pair->left + 1, pair->right + 1);
  r.left = lefts[pair->left], r.right = rights[pair->right];
  r.left.passed_over = int(pair->left), r.right.passed_over = int(pair->right);
}

// Rule 3: both sides found at heights too far apart are neither found.
void refuse_uneven_heights(EarRoots& r, const EarPairFrame& frame, const EarPairOptions& o) {
  if (!r.left.found || !r.right.found) return;
  const std::string why = height_gap_refusal(r.left, r.right, frame, o);
  if (why.empty()) return;
  r.left.found = r.right.found = false;
  r.left.why = r.right.why = why;
}

// Rule 6: one side found alone, no higher than one side alone may lie, stands for both.
void mirror_lone_side(EarRoots& r, const EarInputs& in, const Eigen::Vector3d& d_eye,
                      const EarPairFrame& frame, const EarPairOptions& o, EarPoints& ears) {
  const EarRootSide* lone = r.left.found ? &r.left : r.right.found ? &r.right : nullptr;
  if (!lone) return;
  if (lone->height_mm > o.plausible_highest_mm) {
    r.note = fmt::format(
        "the found one lies {:.1f} mm above its eye corner, over the {:.0f} allowed for one side alone",
        lone->height_mm, o.plausible_highest_mm);
    return;
  }
  const bool left = lone == &r.left;
  const Eigen::Vector3d out_other = (left ? -1.0 : 1.0) * d_eye.normalized();
  (left ? ears.f_l : ears.f_r) = lone->point;
  (left ? ears.f_r : ears.f_l) = mirrored_rest(*lone, left ? in.t_r : in.t_l, out_other, frame);
  r.use = EarRoots::Use::kMirrored;
}

}  // namespace

EarRoots apply_ear_roots(const DensityFn& density, const EarInputs& in, const Eigen::Vector3d& d_eye,
                         double mm_per_unit, const EarRootOptions& options, EarPoints& ears,
                         const EarVeto& accept) {
  const std::vector<EarRootSide> lefts =
      side_lines(density, {in.t_l, in.e_l, d_eye, in.d_up, in.d_fwd, +1, mm_per_unit}, options, accept);
  const std::vector<EarRootSide> rights =
      side_lines(density, {in.t_r, in.e_r, d_eye, in.d_up, in.d_fwd, -1, mm_per_unit}, options, accept);
  EarRoots r;
  r.left = lefts.front(), r.right = rights.front();
  const EarPairFrame frame{in.d_up.normalized(), in.d_fwd.normalized(), mm_per_unit};
  use_agreeing_pair(r, lefts, rights, frame, options);
  refuse_uneven_heights(r, frame, options.pair);
  if (r.left.found && r.right.found) {  // rules 4 and 5
    const Eigen::Vector3d mid = shared_rest(r.left, r.right, frame, options.line.short_line_slices, r.note);
    ears.f_l = frame.level(r.left.point, mid), ears.f_r = frame.level(r.right.point, mid);
    r.use = EarRoots::Use::kBoth;
    return r;
  }
  mirror_lone_side(r, in, d_eye, frame, options.pair, ears);
  return r;
}

}  // namespace lorgnette::fit
