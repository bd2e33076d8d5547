// The head's and the frame's numbers the fit advice compares (fit_advice.h), from the fitted head and
// the placed frame. The frame is taken at its true size on the placement's rotation, resting on the
// head (advice_placement below) whatever the scale policy drew it at, and the head's sizes are in mm through
// the fit's scale:
//   - the face's width at the temples: the head's width where a frame's temples pass it, at the
//     outer eye corners' height, a quarter of the way back from each corner to its ear rest (the
//     synthetic ground truth's definition, synth/procedural_head.cpp), from the density coming in
//     from the side; the landmarks 0 and 16 sit at the tragus, 10-20 mm wider, and are not used;
//   - hinge to ear: each hinge to its ear rest, averaged over the sides, in a straight line: a temple
//     runs straight back from its hinge over the ear's root (where the helix meets the head, the
//     rest), and the length printed on it adds the drop bent down behind the ear (fit_advice.h);
//   - the pupils' height above the lens' centre line, in the frame's canonical axes: the limbus
//     centres (pupil_distance.h) when both eyes' were found; the pupil is centred in the limbus to
//     a fraction of a mm. Else the eye centres, each the mean of its six landmarks (lids and
//     corners), which lie up to ~5 mm above or below the pupil (the lids are not symmetric about
//     it), and the rule says so;
//   - the nose's width where the pads rest: the width of the head's solid cross-section at the lens'
//     centre height, `pad_depth_mm` behind the nose's front there (pads rest on the nose's sides a few
//     mm behind its ridge).
#pragma once
#include <Eigen/Core>
#include <string>

#include "fit/fit_advice.h"
#include "fit/glasses_input.h"
#include "fit/head_probe.h"
#include "fit/place.h"

namespace lorgnette::fit {

struct AdviceHead {
  Eigen::Vector3d eye_l, eye_r, ear_l, ear_r;  // scene; eye_*: the eye centres, ear_*: the ear rests
  Eigen::Vector3d corner_l, corner_r;          // the outer eye corners (landmarks 45 and 36)
  double mm_per_unit = 0.0;
  bool approximate = false;  // the scale is the mean face's
  // The limbus centres (scene) when `limbus`; else `why_no_limbus` (closed eyes, no iris views) and
  // the pupils' height comes from eye_l / eye_r.
  bool limbus = false;
  Eigen::Vector3d pupil_l = Eigen::Vector3d::Zero(), pupil_r = Eigen::Vector3d::Zero();
  std::string why_no_limbus;
};

struct NoseProbeOptions {
  double pad_depth_mm = 5.0;
  double search_mm = 40.0;     // how far in front of and behind the bridge to look for the nose's front
  double step_mm = 0.5;        // probe spacing
  double max_width_mm = 30.0;  // wider: the slice reached the cheeks, not a nose
};

// The frame the advice measures: at its true size on the placement's rotation, resting on the head.
// A stretched frame (policy stretch) is larger than the real one, so its rims meet the nose's flanks
// lower down and the contact search slides it further off the face (14 mm on the procedural head
// with the mean face's scale, against none at true size); the real frame would sit nearer, and its
// hinges nearer the ears. So with any policy other than true size the frame is placed at true size
// from the same points and rested anew (`head` null or without frame points: not rested).
Placement advice_placement(const GlassesRefPoints& glasses, const PlaceInputs& points, ScalePolicy used,
                           const Placement& drawn, const HeadProbe* head, const Eigen::Vector3d& d_fwd);

// Canonical mm of a scene point for the frame at true size: g = g_c + R^T (p - T g_c) mm_per_unit.
Eigen::Vector3d canonical_at_true_size(const Placement& placement, const Eigen::Vector3d& g_c,
                                       double mm_per_unit, const Eigen::Vector3d& scene_point);

// The nose's width (mm) at canonical height `y_mm` for the frame at true size; 0 with `why` when the
// density shows no nose there. `density` is solid above `threshold`.
double nose_width_mm(const DensityFn& density, float threshold, const Placement& placement,
                     const Eigen::Vector3d& g_c, double mm_per_unit, double y_mm,
                     const NoseProbeOptions& options, std::string* why);

struct TempleProbeOptions {
  double depth_share = 0.25;      // from the outer eye corner towards the ear rest
  double reach_mm = 60.0;         // the probe starts this far outside the eye corner
  double inside_corner_mm = 5.0;  // and ends this far inside it
  double step_mm = 0.5;
};

// The face's width (mm) at the temples for the frame at true size (see the top of this file); 0 with
// `why` when the density shows no head side on a probe line.
double temple_width_mm(const DensityFn& density, float threshold, const Placement& placement,
                       const Eigen::Vector3d& g_c, const AdviceHead& head, const TempleProbeOptions& options,
                       std::string* why);

// All four rules' inputs. `density` may be empty (no nose width then).
AdviceInputs advice_inputs(const GlassesInput& glasses, const Placement& placement, const AdviceHead& head,
                           const DensityFn& density, float threshold, const NoseProbeOptions& options = {});

}  // namespace lorgnette::fit
