// What the contact refinement and the temple spread (place.h, temple_fit.h) ask of the head: its
// density, the vertical axis that penetration is measured away from, the scale, what counts as
// solid and which frame samples form the front and the tips. fit_glasses builds one HeadProbe after
// the head frame and the ears, and both stages read it.
#pragma once
#include <Eigen/Core>
#include <functional>
#include <vector>

namespace lorgnette::fit {

// Density of the head at scene points (a NeRF's sigma, or a mesh's inside indicator).
using DensityFn = std::function<std::vector<float>(const std::vector<Eigen::Vector3f>&)>;

// The contact search as a caller sets it (FitOptions::place.contact).
struct ContactSearchOptions {
  double max_shift_mm = 15.0;  // search range along d_fwd, both ways
  double step_mm = 0.25;       // resolution of the search and of the penetration depth
  // Frame points with canonical z above this form the "front". fit_glasses raises it to where the
  // temple spread takes over when the glasses have hinges.
  double front_z_mm = -25.0;
  // The frame rides up the nose (nose_rest.h) at most this far above Eq. 4's height. Where the rule
  // finds a frame resting on its bridge, the rides were 2-7.5 mm (four card captures, in2n-face);
  // higher, the front's upper rims meet the brows (card capture r2_s2 "rested" at 11 mm with its upper
  // inner rims on them, the lenses then too high), and a frame is not worn on its brows. 0: off.
  double max_rise_mm = 8.0;
  double rise_step_mm = 0.5;      // resolution of the height
  double bridge_radius_mm = 4.0;  // front samples this near g_c are the bridge (its underside: g_c)
  // A bridge this near the nose counts as resting on it: the NeRF's skin lies within ~1 mm of the
  // true surface and the skin yields ~0.5 mm under a frame (kFrontToleranceMm, input_checks.h).
  double rest_tolerance_mm = 1.5;
};

// The search plus what the head and the glasses fix: the density that counts as solid and where the
// temple tips begin.
struct ContactOptions : ContactSearchOptions {
  float density_threshold = 10.0f;  // "inside the head" above this (scene-units^-1 for a NeRF)
  // Points behind this canonical z are the temple tips, which wrap behind the ear and press on the
  // skull by design: reported separately (fit_glasses sets it to the ear rest points' z).
  double tip_z_mm = -1e9;
};

struct HeadProbe {
  DensityFn density;
  Eigen::Vector3d axis_point = Eigen::Vector3d::Zero();  // on the head's vertical axis (between the ears)
  Eigen::Vector3d d_up{0, 1, 0};                         // unit
  double mm_per_unit = 1.0;
  ContactOptions contact;
  std::vector<Eigen::Vector3d> frame_points;  // canonical-mm samples of the frame (glasses_input.h)
};

}  // namespace lorgnette::fit
