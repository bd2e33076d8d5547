// Mean-face Procrustes alignment and the head axes of Eq. 1 (see head_frame.h).
#include "fit/head_frame.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "fit/landmark_ids.h"

namespace lorgnette::fit {

SimilarityFit procrustes(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst) {
  if (src.size() != dst.size() || src.size() < 3)
    throw std::runtime_error(
        fmt::format("procrustes: need >= 3 point pairs (got {} and {})", src.size(), dst.size()));
  const int n = int(src.size());
  Eigen::Matrix3Xd a(3, n), b(3, n);
  for (int i = 0; i < n; ++i) a.col(i) = src[i], b.col(i) = dst[i];
  Eigen::Matrix3Xd ac = a.colwise() - a.rowwise().mean();
  Eigen::JacobiSVD<Eigen::Matrix3Xd> svd(ac);
  if (svd.singularValues()(1) < 1e-9 * std::max(1.0, svd.singularValues()(0)))
    throw std::runtime_error("procrustes: the source points are collinear");
  Eigen::Matrix4d t = Eigen::umeyama(a, b, true);  // handles the reflection case (det = -1)
  SimilarityFit out;
  out.scale = t.block<3, 1>(0, 0).norm();
  out.rotation = t.block<3, 3>(0, 0) / out.scale;
  out.translation = t.block<3, 1>(0, 3);
  double sum = 0.0;
  for (int i = 0; i < n; ++i)
    sum += (out.scale * out.rotation * src[i] + out.translation - dst[i]).squaredNorm();
  out.rms = std::sqrt(sum / n);
  return out;
}

HeadFrame estimate_head_frame(const std::vector<Eigen::Vector3d>& landmarks, const std::vector<bool>& valid,
                              const Face68& mean_face) {
  if (landmarks.size() != lm::kCount || valid.size() != lm::kCount || mean_face.size() != lm::kCount)
    throw std::runtime_error("estimate_head_frame: expected 68 landmarks, flags and mean-face points");
  std::vector<Eigen::Vector3d> src, dst;
  for (int i = lm::kRigidFirst; i <= lm::kRigidLast; ++i)
    if (valid[i]) src.push_back(mean_face[i]), dst.push_back(landmarks[i]);
  if (src.size() < 6)
    throw std::runtime_error(fmt::format(
        "only {} of the 31 brow/nose/eye landmarks were triangulated: cannot find the head's front "
        "(try more views or a larger angular range)",
        src.size()));
  if (!valid[lm::kEyeOuterL] || !valid[lm::kEyeOuterR])
    throw std::runtime_error("the outer eye corners (dlib 36, 45) were not triangulated: no eye axis");
  SimilarityFit sim = procrustes(src, dst);
  HeadFrame f;
  f.points_used = int(src.size());
  f.mm_per_unit = 1.0 / sim.scale;
  f.procrustes_rms_mm = sim.rms * f.mm_per_unit;
  Eigen::Vector3d eye = landmarks[lm::kEyeOuterL] - landmarks[lm::kEyeOuterR];
  if (eye.norm() < 1e-9) throw std::runtime_error("degenerate landmarks: the outer eye corners coincide");
  // d_fwd from the 31-point alignment is the better-determined axis: keep it and make the eye axis
  // orthogonal to it (the mean face's own eye corners are 1.3 deg off its front, so taking d_eye
  // raw and re-orthogonalising d_fwd would tilt the forward direction by that much).
  Eigen::Vector3d fwd = sim.rotation.col(2);
  Eigen::Vector3d e = eye.normalized() - eye.normalized().dot(fwd) * fwd;
  if (e.norm() < 0.5)
    throw std::runtime_error(
        "degenerate landmarks: the eye axis is nearly parallel to the face's forward direction");
  f.d_fwd = fwd;
  f.d_eye = e.normalized();
  // Eq. 1 with l = wearer's left: in the right-handed (left, up, forward) frame up = fwd x eye.
  f.d_up = f.d_fwd.cross(f.d_eye);
  Eigen::Vector3d cl = Eigen::Vector3d::Zero(), cr = Eigen::Vector3d::Zero();
  int nl = 0, nr = 0;
  for (int i = lm::kEyeLFirst; i <= lm::kEyeLLast; ++i)
    if (valid[i]) cl += landmarks[i], ++nl;
  for (int i = lm::kEyeRFirst; i <= lm::kEyeRLast; ++i)
    if (valid[i]) cr += landmarks[i], ++nr;
  if (nl > 0 && nr > 0) f.pd_mm = (cl / nl - cr / nr).norm() * f.mm_per_unit;
  return f;
}

}  // namespace lorgnette::fit
