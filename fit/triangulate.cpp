// Least-squares ray intersection with iterative outlier rejection (see triangulate.h).
#include "fit/triangulate.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "fit/camera_math.h"

namespace lorgnette::fit {
namespace {

// Sum of (I - d d^T): the normal matrix of the ray least-squares problem.
Eigen::Matrix3d normal_matrix(const std::vector<Eigen::Vector3d>& dirs) {
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  for (const auto& d : dirs) a += Eigen::Matrix3d::Identity() - d * d.transpose();
  return a;
}

double max_angle_deg(const std::vector<Eigen::Vector3d>& dirs) {
  double best = 0.0;
  for (size_t i = 0; i < dirs.size(); ++i)
    for (size_t j = i + 1; j < dirs.size(); ++j)
      best = std::max(best, std::acos(std::clamp(dirs[i].dot(dirs[j]), -1.0, 1.0)));
  return best * 180.0 / M_PI;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

Eigen::Vector3d nearest_point_to_rays(const std::vector<Eigen::Vector3d>& origins,
                                      const std::vector<Eigen::Vector3d>& dirs) {
  if (origins.size() != dirs.size() || origins.size() < 2)
    throw std::runtime_error(fmt::format("nearest_point_to_rays: need >= 2 rays (got {})", origins.size()));
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < dirs.size(); ++i) {
    Eigen::Vector3d d = dirs[i].normalized();
    Eigen::Matrix3d p = Eigen::Matrix3d::Identity() - d * d.transpose();
    a += p;
    b += p * origins[i];
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(a);
  // The smallest eigenvalue of A vanishes when all rays are parallel (no depth information).
  if (eig.eigenvalues()(0) < 1e-10 * std::max(1.0, eig.eigenvalues()(2)))
    throw std::runtime_error("nearest_point_to_rays: the rays are parallel, the point has no depth");
  return a.ldlt().solve(b);
}

TriangulatedPoint triangulate_point(const std::vector<Observation>& obs, const TriangulateOptions& opt) {
  TriangulatedPoint out;
  std::vector<Ray> rays;
  for (const auto& o : obs) rays.push_back(camera_ray(*o.camera, o.uv));
  std::vector<int> use(obs.size());
  for (size_t i = 0; i < obs.size(); ++i) use[i] = int(i);
  out.reprojection_px.assign(obs.size(), -1.0);
  for (int iter = 0; iter <= opt.max_iterations; ++iter) {
    if (int(use.size()) < std::max(2, opt.min_views)) {
      out.why = fmt::format("only {} of {} views agree (need {})", use.size(), obs.size(),
                            std::max(2, opt.min_views));
      return out;
    }
    std::vector<Eigen::Vector3d> o, d;
    for (int i : use) o.push_back(rays[i].origin), d.push_back(rays[i].dir);
    if (max_angle_deg(d) < opt.min_angle_deg) {
      out.why = fmt::format("the {} rays span {:.2f} deg (< {:.1f}): no depth", d.size(), max_angle_deg(d),
                            opt.min_angle_deg);
      return out;
    }
    out.position = nearest_point_to_rays(o, d);
    std::vector<double> inlier_err;
    for (size_t i = 0; i < obs.size(); ++i) {
      Eigen::Vector2d uv;
      out.reprojection_px[i] =
          camera_project(*obs[i].camera, out.position, &uv) ? (uv - obs[i].uv).norm() : 1e9;
    }
    for (int i : use) inlier_err.push_back(out.reprojection_px[i]);
    double limit = std::max(opt.inlier_px, opt.outlier_factor * median(inlier_err));
    std::vector<int> next;
    for (size_t i = 0; i < obs.size(); ++i)
      if (out.reprojection_px[i] <= limit) next.push_back(int(i));
    if (next == use) break;
    use = next;
  }
  out.inliers = use;
  std::vector<Eigen::Vector3d> d;
  double sum_d2 = 0.0, sum_px2 = 0.0;
  for (int i : use) {
    d.push_back(rays[i].dir);
    Eigen::Vector3d v = out.position - rays[i].origin;
    sum_d2 += (v - v.dot(rays[i].dir) * rays[i].dir).squaredNorm();
    sum_px2 += out.reprojection_px[i] * out.reprojection_px[i];
  }
  size_t n = use.size();
  out.rms_ray_distance = std::sqrt(sum_d2 / n);
  out.rms_reprojection_px = std::sqrt(sum_px2 / n);
  // Each ray constrains 2 of the 3 coordinates: 2n equations, 3 unknowns.
  double dof = std::max(1.0, 2.0 * n - 3.0);
  out.covariance = (sum_d2 / dof) * normal_matrix(d).inverse();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(out.covariance);
  out.sigma = std::sqrt(std::max(0.0, eig.eigenvalues()(2)));
  out.ok = true;
  return out;
}

}  // namespace lorgnette::fit
