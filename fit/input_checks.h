// The fit's checks of its own inputs, and the tolerance of its verdict (#41): a fit is only as good
// as the head it is placed on, and a head with holes (a room model that took part of a pale face
// for the wall behind it) still gives landmarks, a nose point and temples to place a frame on. Each
// check below fails the fit with a reason that says what is wrong and what to film differently:
// - the nose line reads no skin: its colour is darker than any lit skin (the nose is a hole, and the
//   colour field there is the unconstrained black of empty space);
// - landmarks land in empty space: the opacity along their rays, across the skin they should lie
//   on, stays transparent;
// - the temples need more spread than a worn frame bends.
// And the other way: a placement is not failed for a front that touches the face within what the
// NeRF's skin and the skin under the pads allow.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/camera_types.h"
#include "fit/hair.h"
#include "fit/head_probe.h"
#include "fit/temple_fit.h"
#include "fit/triangulate.h"

namespace lorgnette::fit {

// Linear Rec. 709 luminance below which a nose reads no skin: sRGB 13/255. The darkest skin tones in
// lit photos (Fitzpatrick VI) are sRGB ~40-60/255 (linear 0.02-0.045), and the nose line, lit from
// the front, is the face's brightest skin; only empty space, whose colour the NeRF never had to
// explain, reads black (#41: 0.000 on a nose with a hole through it).
constexpr double kMinSkinLuminance = 0.004;

// A landmark lies in empty space when the opacity along its ray, over kSolidReachMm either side of
// it, is under this: the "transparent", at which a render shows what lies behind.
constexpr double kLandmarkOpacity = 0.5;
// A landmark triangulated on the skin lies within a few millimetres of it (the fit snaps landmarks
// onto the skin from up to 12 mm, fit.h); 30 mm either side holds the skin of any landmark of a
// whole face, and a hole in the face leaves it empty.
constexpr double kSolidReachMm = 30.0;
// The fit fails when any of the landmarks it places the frame by (the nose bridge 27-28, the eye
// corners 36, 39, 42, 45) or this share of the inner landmarks (17-67) lies in empty space: a hole
// through the nose (9 landmarks) or a cheek fails; the odd inner lip over an open mouth does not.
constexpr double kEmptyLandmarkShare = 0.1;

// The largest outward spread of a temple (per side, from straight) a worn frame takes: a hinge's
// stop lets a temple open ~5 deg past straight and a spring hinge ~10 deg more; beyond that the
// temple is forced past its hinge and presses on the head. Geometrically, 15 deg moves a temple's
// ear rest, ~100 mm behind the hinge, 26 mm outwards per side: a 52-18 frame (hinges ~69 mm from the
// middle) then clears a head 190 mm wide at the ears, wider than the p99 adult head (170 mm, ANSUR
// II) with 10 mm of hair each side. A head that needs more is wider than any head: what the temples
// meet there is not where a worn temple rests - room haze beside the head (#41: 20 and 16.5 deg on a
// selfie with holes), or the ear's pinna when the frame is turned onto Eq. 2-3's ears (in2n-face's
// left temple: skin-bright, 0.7-0.98 opaque within 4 mm, 73-85 mm behind the hinge).
constexpr double kMaxWornSpreadDeg = 15.0;

// How far the frame's front (rims, bridge, pads) may reach into the face before the fit fails: the
// NeRF's skin lies within ~1 mm of the true surface (the opacity depth the nose point uses: 0.06-0.98
// mm off the meshes of 24 room-capture models, fit.h), and the skin under pads and rims yields by
// ~0.5 mm under a frame's 20-40 g. 1.5 mm = 1 mm of surface uncertainty + 0.5 mm of skin, six steps
// of the contact search; a front deeper than that is visible in a frontal render (#41: a well
// placed seated capture failed at 1.25 mm with 0.5).
constexpr double kFrontToleranceMm = 1.5;

// One check as placement.json's "checks" holds it (placement_json.h): {name: {checked, passed, value,
// limit, reason}}.
struct InputCheck {
  std::string name;      // nose_skin, landmarks_solid, temple_spread, front_penetration
  bool checked = false;  // the input was there to check (colour, landmarks, hinges, contact)
  bool passed = true;
  double value = 0.0, limit = 0.0;  // the figure and its limit, in the check's unit
  std::string reason;               // when not passed: what is wrong and what to do
};

// The nose line's skin: the lower-median luminance of `colour` at the points (dlib 27-30), seen
// along `view_dir` (as hair.h reads the skin's tone). Unchecked when the source has no colour.
InputCheck check_nose_skin(const ColourFn& colour, const std::vector<Eigen::Vector3d>& nose_line,
                           const Eigen::Vector3d& view_dir);

// The opacity along the rays of each triangulated inner landmark (17-67): from the camera of each of
// up to three of its inlier views (`cameras`, indexed as the points' inliers) through the point,
// kSolidReachMm either side of it; a landmark's opacity is the largest over its views.
// `mm_per_unit` converts the reach; `density` is per scene unit.
InputCheck check_landmarks_solid(const DensityFn& density, const std::vector<Camera>& cameras,
                                 const std::vector<TriangulatedPoint>& points, double mm_per_unit);

// The temples' spread against kMaxWornSpreadDeg (unchecked without a temple fit). `ears_estimated`:
// the frame was turned onto Eq. 2-3's ears (the ears' rests not found on the head), which lie 20-40 mm
// behind the ear, so a temple can pass through the ear itself; the reason then says so.
InputCheck check_temple_spread(const TempleFitResult& temples, bool ears_estimated = false);

// The front's penetration after the contact search against `tolerance_mm` (unchecked when the
// contact was not refined).
InputCheck check_front_penetration(bool refined, double front_penetration_mm, double tolerance_mm);

}  // namespace lorgnette::fit
