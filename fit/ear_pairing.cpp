// The ear search's pairing rules (see ear_pairing.h).
#include "fit/ear_pairing.h"

#include <fmt/format.h>

#include <cmath>

namespace lorgnette::fit {

Eigen::Vector2d EarPairFrame::gaps(const EarRootSide& a, const EarRootSide& b) const {
  const Eigen::Vector3d d = (a.point - b.point) * mm_per_unit;
  return Eigen::Vector2d(std::abs(d.dot(up)), std::abs(d.dot(fwd)));
}

bool EarPairFrame::agree(const Eigen::Vector2d& gap, const EarPairOptions& o) const {
  return gap.x() <= o.max_height_gap_mm && gap.y() <= o.max_depth_gap_mm;
}

Eigen::Vector3d EarPairFrame::level(const Eigen::Vector3d& p, const Eigen::Vector3d& target) const {
  return p + (target - p).dot(up) * up + (target - p).dot(fwd) * fwd;
}

std::vector<EarRootSide> accepted_lines(std::vector<EarRootSide> lines, const EarVeto& accept,
                                        const EarPairOptions& o) {
  if (lines.empty() || !lines.front().found) return lines;
  std::vector<EarRootSide> accepted;
  std::string first_veto, next_veto;
  int vetoed = 0;
  for (EarRootSide& line : lines) {
    std::string veto = accept ? accept(line) : std::string();
    if (veto.empty() && &line != lines.data() && line.height_mm > o.plausible_highest_mm)
      veto =
          fmt::format("it lies under hair and {:.1f} mm above the eye corner, over the {:.0f} allowed there",
                      line.height_mm, o.plausible_highest_mm);
    if (veto.empty()) {
      line.higher_vetoed = vetoed;
      accepted.push_back(line);
      continue;
    }
    ++vetoed;
    if (first_veto.empty())
      first_veto =
          fmt::format("{} (a crease {:+.1f} mm above the eye corner, {:+.1f} mm forward of the temple)", veto,
                      line.height_mm, line.depth_mm);
    else if (next_veto.empty())
      next_veto = veto;
  }
  if (!accepted.empty()) return accepted;
  EarRootSide s = lines.front();
  s.found = false, s.vetoed = true;
  s.why = lines.size() == 1 ? first_veto
                            : fmt::format("{}; and the {} lower line(s) of creases too (the highest: {})",
                                          first_veto, lines.size() - 1, next_veto);
  return {s};
}

std::optional<EarLinePair> agreeing_pair(const std::vector<EarRootSide>& lefts,
                                         const std::vector<EarRootSide>& rights, const EarPairFrame& frame,
                                         const EarPairOptions& o, int short_line_slices) {
  auto may_stand_in = [&](const EarRootSide& line, size_t place) {
    return place == 0 || line.slices >= short_line_slices;
  };
  size_t best_l = 0, best_r = 0, best_rank = 0;
  double best_depth_gap = 0.0;
  for (size_t i = 0; i < lefts.size(); ++i)
    for (size_t j = 0; j < rights.size(); ++j) {
      const Eigen::Vector2d gap = frame.gaps(lefts[i], rights[j]);
      if (!frame.agree(gap, o) || !may_stand_in(lefts[i], i) || !may_stand_in(rights[j], j)) continue;
      if (best_rank == 0 || i + j < best_rank || (i + j == best_rank && gap.y() < best_depth_gap))
        best_l = i, best_r = j, best_rank = i + j, best_depth_gap = gap.y();
    }
  if (best_rank == 0) return std::nullopt;  // (0 + 0 is the first pair, which the caller found apart)
  return EarLinePair{best_l, best_r};
}

std::string height_gap_refusal(const EarRootSide& left, const EarRootSide& right, const EarPairFrame& frame,
                               const EarPairOptions& o) {
  const double gap = frame.gaps(left, right).x();
  if (gap <= o.max_height_gap_mm) return {};
  return fmt::format(
      "the two sides' rests lie {:.1f} mm apart in height (over {:.0f}; left {:+.1f} mm above its eye "
      "corner, "
      "right {:+.1f})",
      gap, o.max_height_gap_mm, left.height_mm, right.height_mm);
}

Eigen::Vector3d shared_rest(const EarRootSide& left, const EarRootSide& right, const EarPairFrame& frame,
                            int short_line_slices, std::string& note) {
  Eigen::Vector3d mid = 0.5 * (left.point + right.point);
  const bool short_l = left.slices < short_line_slices, short_r = right.slices < short_line_slices;
  if (short_l == short_r) return mid;
  const EarRootSide& whole = short_l ? right : left;
  mid += (whole.point - mid).dot(frame.fwd) * frame.fwd;  // the height stays the mean: both lie on the top
  note += fmt::format("{}the {} side's line holds {} depths: the rests' depth is the {} side's",
                      note.empty() ? "" : "; ", short_l ? "left" : "right", (short_l ? left : right).slices,
                      short_l ? "right" : "left");
  return mid;
}

Eigen::Vector3d mirrored_rest(const EarRootSide& found, const Eigen::Vector3d& other_temple,
                              const Eigen::Vector3d& out_other, const EarPairFrame& frame) {
  const Eigen::Vector3d beside = other_temple + found.lateral_mm * out_other / frame.mm_per_unit;
  return frame.level(beside, found.point);
}

}  // namespace lorgnette::fit
