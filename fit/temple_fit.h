// The temple spread search that follows the contact refinement: the rigid frame's temples often
// pass into the head behind the ears (heads are wider there than frames). Real temples spring open
// at the hinges; per side this finds the smallest outward spread (mesh/temple_bend.h, the same
// deformation the renderer applies) at which that temple's samples — from the hinge back, tips
// behind the ear rests included — penetrate the head by at most the allowed depth, measured as
// penetration_depth_mm does (place.h). Angles are tried in order, step_deg apart, up to
// max_spread_deg; a side that is still clipping there keeps the maximum and is reported unclear.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "fit/head_probe.h"
#include "mesh/temple_bend.h"

namespace lorgnette::fit {

struct TempleFitOptions {
  bool enabled = true;
  double max_spread_deg = 25.0;  // beyond this a temple would break, not flex
  double step_deg = 0.25;        // resolution of the search
  double ramp_mm = 4.0;          // smooth transition behind the hinge (TempleBend::ramp_mm)
};

struct TempleSideFit {
  double spread_deg = 0.0;             // chosen outward spread
  double penetration_before_mm = 0.0;  // this temple, rigid (spread 0)
  double penetration_mm = 0.0;         // this temple at spread_deg
  int points = 0;                      // frame samples on this temple
  bool clear = true;                   // penetration_mm <= the allowed depth
};

struct TempleFitResult {
  bool fitted = false;    // the search ran (the glasses have hinges, the option is on)
  mesh::TempleBend bend;  // hinges and chosen spreads: what placement.json carries, what render applies
  TempleSideFit left, right;
};

struct TempleFitInputs {
  Eigen::Matrix4d transform = Eigen::Matrix4d::Identity();  // canonical mm -> scene, after refine_contact
  Eigen::Vector3d hinge_l{0, 0, 0}, hinge_r{0, 0, 0};       // canonical mm
};

// The probe's frame points are the samples searched; `max_penetration_mm`: the allowed depth.
TempleFitResult fit_temples(const TempleFitInputs& in, const HeadProbe& head, double max_penetration_mm,
                            const TempleFitOptions& options);

// One warning per temple that still clips at the largest spread (empty: the temples fit). The
// fit's verdict fails on any: the frame is too narrow for this head.
std::vector<std::string> temple_warnings(const TempleFitResult& result);

}  // namespace lorgnette::fit
