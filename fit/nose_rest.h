// How high the frame's front rests on the nose (the contact refinement's first step, place.h). Eq. 4
// puts the bridge g_c on the nose point f_c; a frame is worn where its front can rest against the face
// with its bridge on the nose. Where the nose, at the height of the lower inner rims, is wider than the
// frame's bridge, the rims meet the nose's sides and the cheeks beside it before the bridge meets the
// nose: a worn frame then rides up the nose until its bridge does rest on it, where the nose is no
// wider than the bridge, and sits higher. Sliding along the face's forward axis alone cannot find
// that: it floats the frame in front of the face until the rims clear the nose's sides (both real
// captures: 15 mm, the search's whole range, with the front still inside).
//
// The frame rides up about the axis through the ears, on which its temples rest: its bridge rises by
// u and its lower rims tilt out from the face (about 0.6 deg per mm of rise with the ears 100 mm
// behind the bridge), as a frame pushed up the nose does.
//
// The rule: at each height u above Eq. 4's (0, rise_step_mm, ... max_rise_mm) the front rests at the smallest
// forward shift at which it clears the head, s(u); its bridge alone (the front's samples within
// bridge_radius_mm of g_c) would rest at n(u). The gap s(u) - n(u) is how far the bridge floats in front of
// the nose because something else holds the frame (0: the bridge holds it). The frame rests at the lowest
// height whose gap is within rest_tolerance_mm of the smallest gap over all heights: gravity keeps a frame as
// low as it can rest on its bridge. A frame that rests on its bridge at Eq. 4's height (gap within the
// tolerance there) stays there, and so does one whose bridge never meets the nose (a frame with pads: its
// gaps are alike at every height).
#pragma once
#include <Eigen/Core>
#include <limits>
#include <vector>

#include "fit/head_probe.h"

namespace lorgnette::fit {

using PointSets = std::vector<std::vector<Eigen::Vector3d>>;

// Per set of scene points: the smallest shift k * step_mm (|k| <= max_shift_mm / step_mm) along
// `mm_fwd` (one millimetre along d_fwd, in scene units) at which none of the set's points is inside
// the head (density above `threshold`). Clearance is taken as monotone in the shift (moving away from
// the face never enters it), which lets a bisection find it in ~9 density queries, every set batched.
// +infinity: still inside at +max_shift_mm; -infinity: clear at -max_shift_mm (nothing to rest on).
std::vector<double> clearing_shifts_mm(const DensityFn& density, float threshold, const PointSets& sets,
                                       const Eigen::Vector3d& mm_fwd, double step_mm, double max_shift_mm);

struct NoseRest {
  double rise_mm = 0.0;                                         // chosen height above Eq. 4's
  size_t chosen = 0;                                            // its index in the profile
  std::vector<double> heights_mm, shifts_mm, bridge_shifts_mm;  // the profile: u, s(u), n(u)
  // s(u) - n(u); +infinity where the front cannot clear or its bridge meets nothing.
  double gap_mm(size_t i) const;
};

// The rule above. Per height u in `heights_mm` (ascending, the first 0): the front's scene samples
// and its bridge's as the frame stands raised by u (place.cpp turns it about the ears).
NoseRest nose_rest(const HeadProbe& head, const std::vector<double>& heights_mm, const PointSets& front,
                   const PointSets& bridge, const Eigen::Vector3d& mm_fwd);

}  // namespace lorgnette::fit
