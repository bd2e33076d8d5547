// The two temples (dlib 0 and 16, the ends of the jaw contour that hang the ear search and Eq. 2-3)
// at one depth. Each is cast onto the head's surface from the views that show its side, at the depth
// where the ray's opacity reaches 0.5 (surface_landmarks.h). Those rays meet the side of the head at
// grazing angles, so a cast's depth along d_fwd is ill-conditioned both ways: where the capture saw a
// side only at grazing angles (a +-20 deg arc, a room model's soft sides) the opacity builds up over
// 10-40 mm and the 0.5 level lies that far behind the skin; where a NeRF leaves faint haze along the
// side of the face (a small, low-resolution capture), a grazing ray gathers its opacity in the haze
// and the cast lands up to 20 mm in front of it (docs/fit.md, "The temples at one depth"). A head's
// temples lie at nearly one depth (1.8 mm apart on the Lee Perry-Smith scan, 0.9 mm on the
// procedural head), so when they lie more than `max_gap_mm` apart one of them is wrong, and its own
// rays cannot tell which. A horizontal ray from outside along the head's left-right axis meets the
// side square on, where a cast's error shows as a gap across the skin: the cast of a soft side or of
// haze lies off the skin that the density shows from the side (outside it, or inside behind the
// skin's front), a good cast lies on it. So the temple whose cast lies further from the skin seen from
// the side is moved along its own rays to the other's depth (forward or back): its width and height
// stay its own views', its depth is the better-supported side's.
#pragma once
#include <string>
#include <vector>

#include "fit/head_frame.h"
#include "fit/triangulate.h"
#include "fit/view_source.h"

namespace lorgnette::fit {

struct ViewRecord;  // detect_views.h

struct TempleDepthOptions {
  bool enabled = true;
  // Temples further apart than this along d_fwd are made one depth. A 1 deg error of the head's yaw
  // alone shifts them ~2.8 mm apart (160 mm between them); the scan's true temples are 1.8 mm apart.
  double max_gap_mm = 5.0;
  // The side probe starts this far outside each cast and ends as far inside: the casts of a soft side
  // or of haze lie up to ~15 mm off the side's skin, a good one within ~2 mm.
  double probe_mm = 30.0;
};

struct TempleDepthResult {
  double gap_mm = 0.0;  // left minus right along d_fwd, before (mm; > 0: the left is further forward)
  // Each cast's distance from the skin met by the side probe (mm; +inf: the probe met no skin).
  double off_skin_l_mm = 0.0, off_skin_r_mm = 0.0;
  int moved = 0;                // +1: the left temple was moved to the right's depth, -1: the right, 0: none
  int rays = 0;                 // rays that placed the moved temple
  std::string summary() const;  // for the log: what was moved, by how much, and why
};

// How far `point` lies from the skin that a horizontal ray from outside along `side` (+1: the
// wearer's left, d_eye) meets at its height and depth, at opacity 0.5, in mm: |signed distance|, or
// +inf when the probe meets nothing within `probe_mm` either side of the point.
double off_skin_mm(ViewSource& source, const HeadFrame& head, const Eigen::Vector3d& point, int side,
                   double probe_mm);

// Applies the rule to points[lm::kTempleL] / points[lm::kTempleR] (their `inliers` index `views`,
// as cast_surface_landmarks leaves them). A temple without usable rays is left where it is.
TempleDepthResult balance_temple_depths(ViewSource& source, const std::vector<ViewRecord>& views,
                                        const HeadFrame& head, const TempleDepthOptions& options,
                                        std::vector<TriangulatedPoint>& points);

}  // namespace lorgnette::fit
