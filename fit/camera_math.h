// Eigen-typed views of the shared Camera model (kernels/common/camera_types.h): rays through pixels,
// projection of points, and look-at construction of camera-to-world matrices. The fit works on
// Eigen types; these thin wrappers keep the one camera rule (the LGN_INLINE functions) in charge.
#pragma once
#include <Eigen/Core>

#include "common/camera_types.h"

namespace lorgnette::fit {

struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d dir;  // unit length
};

// The ray through continuous pixel coordinates (u, v) (pixel centres at i + 0.5).
Ray camera_ray(const Camera& cam, const Eigen::Vector2d& uv);

// Projects a world point; returns false when it lies behind the camera.
bool camera_project(const Camera& cam, const Eigen::Vector3d& p, Eigen::Vector2d* uv);

// Camera centre and unit viewing direction (-z of the camera) in world space.
Eigen::Vector3d camera_center(const Camera& cam);
Eigen::Vector3d camera_forward(const Camera& cam);

// A pinhole camera at `eye` looking at `target` with the world `up` hint, vertical field of view
// `fov_y_deg`, square pixels, principal point at the image centre, no distortion.
Camera look_at_camera(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, const Eigen::Vector3d& up,
                      double fov_y_deg, int width, int height);

}  // namespace lorgnette::fit
