// The head's orientation and metric scale from triangulated landmarks (paper Sec. 3.1, Eq. 1): a
// similarity Procrustes alignment (Umeyama) of the 68-point mean face onto the landmarks gives the
// forward direction d_fwd and millimetres per scene unit; Eq. 1 then fixes d_eye from the outer eye
// corners and d_up. Axes follow the glasses canonical frame: x = wearer's left, y = up, z = forward.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

namespace lorgnette::fit {

// 68 points in millimetres in the head frame (x left, y up, z forward out of the face).
using Face68 = std::vector<Eigen::Vector3d>;

struct SimilarityFit {
  double scale = 1.0;                                      // scene units per mm
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // head frame -> scene
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double rms = 0.0;  // residual, scene units
};

// Similarity (s, R, t) minimising sum |s R src_i + t - dst_i|^2 over the pairs (Umeyama, proper
// rotation). Throws when fewer than 3 pairs or the points are collinear.
SimilarityFit procrustes(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst);

struct HeadFrame {
  Eigen::Vector3d d_fwd, d_up, d_eye;  // orthonormal, right-handed: d_eye x d_up = d_fwd
  double mm_per_unit = 0.0;
  double pd_mm = 0.0;  // distance between the eye centres
  double procrustes_rms_mm = 0.0;
  int points_used = 0;
};

// Aligns `mean_face` to the landmarks flagged in `valid` (rigid set: brows, nose, eyes) and builds the
// frame. d_fwd is the aligned mean face's forward; d_eye the outer eye-corner axis (Eq. 1) made
// orthogonal to it; d_up = d_fwd x d_eye. Throws with the reason when too few landmarks or degenerate
// geometry.
HeadFrame estimate_head_frame(const std::vector<Eigen::Vector3d>& landmarks, const std::vector<bool>& valid,
                              const Face68& mean_face);

}  // namespace lorgnette::fit
