// The 2D facial layout of the procedural head, in the frontal plane of the head frame (millimetres,
// x towards the wearer's left = image right in a frontal view, y up, y = 0 at eye level, x = 0 on
// the midline). One construction drives both the painted texture and the 68 iBUG landmark
// positions, so painted features and landmarks agree by design: the eye is the region between two
// lid curves that meet at the corners (landmarks 36/39, 42/45) and pass through the lid landmarks;
// brows, lips and nose are curves through their landmarks. Proportions follow the usual adult
// anthropometry (the widely used 68-point mean shape, re-derived from the parameters).
#pragma once
#include <Eigen/Core>
#include <array>
#include <vector>

#include "synth/head_params.h"

namespace lorgnette::synth {

// The lids' height profile along the eye, t in [0, 1] from the outer to the inner corner (clamped):
// 0 at the corners, 1 mid-eye. EyeShape's lid curves and the painted lids share it.
float lid_bump(float t);

struct EyeShape {
  Eigen::Vector2f outer, inner;  // corners
  float upper_height = 5.5f;     // lid curve heights above / below the corner line
  float lower_height = 3.0f;
  Eigen::Vector2f centre() const { return 0.5f * (outer + inner) + Eigen::Vector2f(0.0f, 1.0f); }
  // t in [0, 1] from outer to inner corner: points on the lid curves.
  Eigen::Vector2f upper(float t) const;
  Eigen::Vector2f lower(float t) const;
};

struct FaceLayout {
  std::array<Eigen::Vector2f, 68> ibug;  // iBUG 300-W order (0-16 jaw, 17-26 brows, ..., 60-67 inner lips)
  EyeShape eye_r, eye_l;                 // wearer's right (image left, landmarks 36-41) and left (42-47)
  float iris_radius = 5.9f;
  float pupil_radius = 2.4f;
  std::vector<Eigen::Vector2f> brow_r, brow_l;    // dense curves (outer to inner)
  std::vector<Eigen::Vector2f> upper_lip_top;     // dense curve 48 -> 54 through 49-53
  std::vector<Eigen::Vector2f> lower_lip_bottom;  // dense curve 54 -> 48 through 55-59
  float mouth_y = -64.0f;                         // lip line height at the corners
  float mouth_half_width = 28.0f;
  float lip_line_lift = 1.0f;            // lip line centre above the corners
  Eigen::Vector2f nostril_r, nostril_l;  // nostril centres
  float lip_line_y(float x) const;       // closed-mouth lip line
};

FaceLayout make_face_layout(const HeadParams& p);

// Dense Catmull-Rom curve through the points (`per_segment` samples per segment).
std::vector<Eigen::Vector2f> catmull_rom(const std::vector<Eigen::Vector2f>& pts, int per_segment);
// Distance from q to a polyline; `t` (optional) receives the arc-length fraction of the closest point.
float polyline_distance(const std::vector<Eigen::Vector2f>& line, const Eigen::Vector2f& q,
                        float* t = nullptr);
// Height of a curve that is a function of x (sampled densely, x monotonic) at x; NaN outside.
float curve_y_at(const std::vector<Eigen::Vector2f>& curve, float x);

}  // namespace lorgnette::synth
