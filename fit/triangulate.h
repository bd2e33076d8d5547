// Multi-view triangulation of 2D landmarks: each 3D point is the least-squares point nearest to all
// of its rays (the paper's rule, Sec. 3.1), made robust to wrong detections by rejecting views whose
// reprojection error is far above the rest and re-solving, with a per-point uncertainty (covariance
// of the least-squares solution scaled by the residual ray distances).
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/camera_types.h"

namespace lorgnette::fit {

// One observation of a point: the camera and the pixel where the detector put it.
struct Observation {
  const Camera* camera = nullptr;
  Eigen::Vector2d uv;
};

struct TriangulateOptions {
  int min_views = 2;            // fewer inliers than this -> not ok
  double inlier_px = 4.0;       // a view is always kept when its reprojection error is below this
  double outlier_factor = 3.0;  // ... and rejected above max(inlier_px, factor * median error)
  int max_iterations = 5;
  double min_angle_deg = 2.0;  // rays spanning less than this give no depth -> degenerate
};

struct TriangulatedPoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // scene units^2
  double sigma = 0.0;                   // sqrt of the largest covariance eigenvalue (scene units)
  double rms_ray_distance = 0.0;        // scene units, inliers
  double rms_reprojection_px = 0.0;     // inliers
  std::vector<int> inliers;             // indices into the observation list
  std::vector<double> reprojection_px;  // per observation (all of them), -1 when behind a camera
  bool ok = false;
  std::string why;  // when !ok: what went wrong
};

// The point minimising the sum of squared distances to the rays; throws std::runtime_error when the
// rays are (nearly) parallel or fewer than two are given.
Eigen::Vector3d nearest_point_to_rays(const std::vector<Eigen::Vector3d>& origins,
                                      const std::vector<Eigen::Vector3d>& dirs);

// Robust triangulation of one point from its observations (never throws on bad data: ok/why say).
TriangulatedPoint triangulate_point(const std::vector<Observation>& obs, const TriangulateOptions& opt = {});

}  // namespace lorgnette::fit
