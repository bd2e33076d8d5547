// The two temples (dlib 0 and 16, the ends of the jaw contour that Eq. 2-3 turn into the ear rests)
// at a consistent depth. Each is cast onto the head's surface from the views that show its side, at
// the depth where the ray's opacity reaches 0.5 (surface_landmarks.h). Where the capture saw that
// side of the head only at grazing angles (a +-20 deg arc, or the room model's softer sides), the
// NeRF's surface there is soft: the opacity builds up over 10-20 mm, its 0.5 level lies that far
// behind the skin, and the temple, hence the ear, goes back with it. On three synthetic room captures
// whose true meshes were known, the ears missed by 7-15 mm that way while the other side was within
// 4 mm (docs/fit.md, "The temples at one depth"). A softer surface only ever moves the opacity
// depth back (thin floaters in front reach little opacity), and a head's temples lie at nearly one
// depth along its forward axis (1.8 mm apart on the Lee Perry-Smith scan, 0.9 mm on the procedural
// head). So when one temple lies more than `max_gap_mm` behind the other, it is moved along its own
// rays to the other's depth: its width and height stay its own views', its depth is the better
// side's.
#pragma once
#include <string>
#include <vector>

#include "fit/head_frame.h"
#include "fit/triangulate.h"

namespace lorgnette::fit {

struct ViewRecord;  // detect_views.h

struct TempleDepthOptions {
  bool enabled = true;
  // Temples further apart than this along d_fwd are made one depth. A 1 deg error of the head's yaw
  // alone shifts them ~2.8 mm apart (160 mm between them); the scan's true temples are 1.8 mm apart.
  double max_gap_mm = 5.0;
};

struct TempleDepthResult {
  double gap_mm = 0.0;          // left minus right along d_fwd, before (mm; > 0: the left is further forward)
  int moved = 0;                // +1: the left temple was moved forward, -1: the right, 0: none
  int rays = 0;                 // rays that placed the moved temple
  std::string summary() const;  // for the log: what was moved, by how much, and why
};

// Applies the rule to points[lm::kTempleL] / points[lm::kTempleR] (their `inliers` index `views`,
// as cast_surface_landmarks leaves them). A temple without usable rays is left where it is.
TempleDepthResult balance_temple_depths(const std::vector<ViewRecord>& views, const HeadFrame& head,
                                        const TempleDepthOptions& options,
                                        std::vector<TriangulatedPoint>& points);

}  // namespace lorgnette::fit
