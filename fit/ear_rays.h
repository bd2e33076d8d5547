// The ear search's ray field (docs/fit.md, "The ear search"): vertical rays cast down (along -d_up)
// in a window beside the head, behind the temple landmark, each stopped where its opacity from above
// reaches a level. A ray meets the skull's side or the top of the ear; the heights where they stop,
// read across the window at one depth, are the profile the crease finder (ear_lines.h) reads.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "fit/head_probe.h"

namespace lorgnette::fit {

// The window, in mm from the temple landmark: along d_fwd (negative = behind it), outwards along the
// side's d_eye, and along d_up from the outer eye corner's height; the steps between rays and along
// them; and the opacity at which a ray meets the head. The window reaches behind dlib's temple, which
// lies at the ear's front (in front of it lies hair over the temple). A NeRF's ear top is soft (the
// capture sees it only at grazing angles), so the level is low: at 0.5 the rays met the procedural
// heads' NeRF ears 1.3-3.1 mm under the exact mesh's.
struct EarRayOptions {
  double back_mm = 35.0, front_mm = 0.0;
  double inward_mm = 12.0, outward_mm = 30.0;
  double above_mm = 50.0, below_mm = 30.0;
  double depth_step_mm = 2.0, lateral_step_mm = 1.0, ray_step_mm = 0.5;
  double opacity = 0.25;  // (0, 1): the ray's accumulated opacity where it meets the head
};

// One side of the head: where the search's window sits.
struct EarRootInputs {
  Eigen::Vector3d temple;              // the side's temple landmark (scene)
  Eigen::Vector3d eye_corner;          // the side's outer eye corner (scene): the window's height
  Eigen::Vector3d d_eye, d_up, d_fwd;  // the head frame (unit; d_eye towards the wearer's left)
  int side = +1;                       // +1 = the wearer's left, -1 = right
  double mm_per_unit = 0.0;
};

// The side's axes, to turn the search's millimetres (outwards, forward of the temple, above the eye
// corner) into scene points.
struct EarSideFrame {
  explicit EarSideFrame(const EarRootInputs& in);
  Eigen::Vector3d point(double lateral_mm, double depth_mm, double height_mm) const;

  Eigen::Vector3d temple, out, up, fwd;
  double eye_height_mm = 0.0;  // the eye corner above the temple
  double mm_per_unit = 0.0;
};

// The rays' stops: heights[i][j] (mm above the eye corner; NaN where the ray met nothing) of the ray
// at depths[i] (mm along d_fwd from the temple) and laterals[j] (mm outwards along the side's d_eye).
struct EarRayField {
  std::vector<double> depths, laterals;
  std::vector<std::vector<double>> heights;
};

// Throws std::invalid_argument on a non-positive scale or step, a side other than +-1, an empty window
// or an opacity outside (0, 1).
void check_ear_search(const EarRootInputs& in, const EarRayOptions& o);

// `from`, `from + step`, ... up to `to` (inclusive within 1e-9).
std::vector<double> ear_grid(double from, double to, double step);

// The rays at `depths_mm` across the window's width, with one density query for all of them (a ray's
// opacity integrates the density by the trapezoid rule along its samples, from the window's top down).
EarRayField cast_ear_rays(const DensityFn& density, const EarRootInputs& in, const EarRayOptions& o,
                          const std::vector<double>& depths_mm);

}  // namespace lorgnette::fit
