// Ear rest points and the nose point (paper Sec. 3.1, Eq. 2-3). The temple landmark is moved along
// d_up to the height of the outer eye corner (Eq. 2), then back along d_fwd by alpha times the outer
// eye-corner distance (Eq. 3). Temples are dlib 0 and 16 (the top of the jaw contour, beside the
// tragus: the nearest dlib points to the paper's FaceMesh temple landmarks); the nose point f_c is a
// blend of the nose-bridge points 27 (between the eyes) and 28 (one step down the bridge), where a
// frame's bridge rests.
#pragma once
#include <Eigen/Core>

namespace lorgnette::fit {

struct EarInputs {
  Eigen::Vector3d e_l, e_r;     // outer eye corners (dlib 45 = left, 36 = right)
  Eigen::Vector3d t_l, t_r;     // temples (dlib 16 = left, 0 = right)
  Eigen::Vector3d d_up, d_fwd;  // unit
};

struct EarPoints {
  Eigen::Vector3d f_l, f_r;
  Eigen::Vector3d t_hat_l, t_hat_r;  // temples projected to the eye height (Eq. 2)
};

// Eq. 2-3 (alpha = 0.5 in the paper). d_up need not be unit in Eq. 2's first form; we normalise.
EarPoints ear_points(const EarInputs& in, double alpha = 0.5);

// f_c = (1 - w) * p27 + w * p28.
Eigen::Vector3d nose_point(const Eigen::Vector3d& p27, const Eigen::Vector3d& p28, double w = 0.5);

}  // namespace lorgnette::fit
