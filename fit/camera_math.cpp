// Eigen wrappers over the shared camera header (see camera_math.h).
#include "fit/camera_math.h"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

namespace lorgnette::fit {

Ray camera_ray(const Camera& cam, const Eigen::Vector2d& uv) {
  LgnVec3 d = ::camera_ray_dir(&cam, static_cast<float>(uv.x()), static_cast<float>(uv.y()));
  Ray r;
  r.origin = camera_center(cam);
  r.dir = Eigen::Vector3d(d.x, d.y, d.z).normalized();
  return r;
}

bool camera_project(const Camera& cam, const Eigen::Vector3d& p, Eigen::Vector2d* uv) {
  float u = 0, v = 0;
  float depth = ::camera_project(&cam, lgn_vec3(float(p.x()), float(p.y()), float(p.z())), &u, &v);
  *uv = Eigen::Vector2d(u, v);
  return depth > 0.0f;
}

Eigen::Vector3d camera_center(const Camera& cam) {
  return Eigen::Vector3d(cam.c2w[3], cam.c2w[7], cam.c2w[11]);
}

Eigen::Vector3d camera_forward(const Camera& cam) {
  return -Eigen::Vector3d(cam.c2w[2], cam.c2w[6], cam.c2w[10]).normalized();
}

Camera look_at_camera(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, const Eigen::Vector3d& up,
                      double fov_y_deg, int width, int height) {
  Eigen::Vector3d back = eye - target;  // camera +z points away from what it looks at
  if (back.norm() < 1e-12) throw std::runtime_error("look_at_camera: eye and target coincide");
  if (up.cross(back.normalized()).norm() < 1e-9)
    throw std::runtime_error("look_at_camera: up is parallel to the view direction");
  auto v = [](const Eigen::Vector3d& p) { return lgn_vec3(float(p.x()), float(p.y()), float(p.z())); };
  return camera_look_at(v(eye), v(target), v(up), float(fov_y_deg), static_cast<lgn_uint>(width),
                        static_cast<lgn_uint>(height));
}

}  // namespace lorgnette::fit
