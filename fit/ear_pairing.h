// The ear search's pairing (docs/fit.md, "The ear search"): from each side's lines of creases
// (ear_lines.h), the two rests the fit uses, or one side's rest mirrored onto the other, or none
// (Eq. 2-3's ears stand). Each rule is a function of its own; apply_ear_roots (ear_root.h) runs them
// in the order listed here.
#pragma once
#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "fit/ear_lines.h"

namespace lorgnette::fit {

// How far the two sides' rests may lie apart, and how high a rest without a second witness may lie.
// - A head's ears lie at one height (their heights set the frame's pitch): within `max_height_gap_mm`.
// - And at one depth, give or take the scatter along the root's flat top: within `max_depth_gap_mm`
//   (infinity: each side's first line, whatever the gap).
// - The rests of every head we know lie -5..+17 mm above the eye corners, hair's creases higher: a rest
//   with no second witness (under hair or a higher line, or one side alone) lies at most
//   `plausible_highest_mm` above its eye corner.
struct EarPairOptions {
  double max_height_gap_mm = 15.0;
  double max_depth_gap_mm = 12.0;
  double plausible_highest_mm = 20.0;
};

// A caller's veto on a line (e.g. its ear top is as dark as hair): the reason, or empty to accept it.
using EarVeto = std::function<std::string(const EarRootSide&)>;

// The head's vertical and forward axes and its scale: two rests' gaps in mm.
struct EarPairFrame {
  Eigen::Vector3d up, fwd;  // unit
  double mm_per_unit = 0.0;
  // |height| and |depth| of a - b (mm).
  Eigen::Vector2d gaps(const EarRootSide& a, const EarRootSide& b) const;
  bool agree(const Eigen::Vector2d& gap, const EarPairOptions& o) const;
  // `p` moved to `target`'s height and depth, at its own width.
  Eigen::Vector3d level(const Eigen::Vector3d& p, const Eigen::Vector3d& target) const;
};

// Rule 1, the veto: a side's lines that `accept` accepts, highest first, each counting the higher lines
// refused. A line under another (refused or not) must also lie no higher than plausible_highest_mm:
// hair's lower edges make creases too. When `lines` holds no line found, it is returned as it is;
// when every line is refused, one side not found and vetoed, saying why.
std::vector<EarRootSide> accepted_lines(std::vector<EarRootSide> lines, const EarVeto& accept,
                                        const EarPairOptions& o);

// Rule 2, a pair that agrees: where the two first lines lie too far apart (height or depth), the pair
// of lines, one per side, that agrees and ranks highest together (the least sum of places), then the
// closest in depth. A line that stands in for its side's first spans at least `short_line_slices`
// depths (short lines lie at the window's back edge, or on hair's edge). None: no other pair agrees.
struct EarLinePair {
  size_t left = 0, right = 0;  // places in each side's list
};
std::optional<EarLinePair> agreeing_pair(const std::vector<EarRootSide>& lefts,
                                         const std::vector<EarRootSide>& rights, const EarPairFrame& frame,
                                         const EarPairOptions& o, int short_line_slices);

// Rule 3, one height: two rests further apart in height than max_height_gap_mm are not two ears' roots;
// the reason, or empty when they agree.
std::string height_gap_refusal(const EarRootSide& left, const EarRootSide& right, const EarPairFrame& frame,
                               const EarPairOptions& o);

// Rules 4 and 5, the shared rest: both rests at the mean height and depth of the two (a difference within
// the limits is the search's scatter more than the head's asymmetry, and would yaw or roll the frame),
// except that a line over fewer than `short_line_slices` depths opposite one at least that long is a
// fragment of its root, whose front end is not where the root leaves the head: the depth is then the
// long line's alone. Returns the shared height-and-depth point; `note` says when the fragment rule held.
Eigen::Vector3d shared_rest(const EarRootSide& left, const EarRootSide& right, const EarPairFrame& frame,
                            int short_line_slices, std::string& note);

// Rule 6, one side mirrored: the other side's rest at the found one's height and depth, as far out from
// its own temple (`other_temple`, `out_other`: that side's outward unit axis) as the found one.
Eigen::Vector3d mirrored_rest(const EarRootSide& found, const Eigen::Vector3d& other_temple,
                              const Eigen::Vector3d& out_other, const EarPairFrame& frame);

}  // namespace lorgnette::fit
