// Eq. 2-3 of the paper (see ears.h).
#include "fit/ears.h"

namespace lorgnette::fit {
namespace {

Eigen::Vector3d project_to_eye_height(const Eigen::Vector3d& t, const Eigen::Vector3d& e,
                                      const Eigen::Vector3d& up) {
  return t + ((e - t).dot(up) / up.dot(up)) * up;  // Eq. 2
}

}  // namespace

EarPoints ear_points(const EarInputs& in, double alpha) {
  EarPoints out;
  out.t_hat_l = project_to_eye_height(in.t_l, in.e_l, in.d_up);
  out.t_hat_r = project_to_eye_height(in.t_r, in.e_r, in.d_up);
  double back = alpha * (in.e_l - in.e_r).norm();
  Eigen::Vector3d fwd = in.d_fwd.normalized();
  out.f_l = out.t_hat_l - back * fwd;  // Eq. 3
  out.f_r = out.t_hat_r - back * fwd;
  return out;
}

Eigen::Vector3d nose_point(const Eigen::Vector3d& p27, const Eigen::Vector3d& p28, double w) {
  return (1.0 - w) * p27 + w * p28;
}

}  // namespace lorgnette::fit
