// Orbit cameras, the cap of views and the front sweep (see view_planning.h).
#include "fit/view_planning.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "fit/camera_math.h"

namespace lorgnette::fit {

Camera orbit_camera(const Orbit& o, double yaw_deg, double pitch_deg) {
  const double yaw = yaw_deg * M_PI / 180.0, pitch = pitch_deg * M_PI / 180.0;
  Eigen::Vector3d up = o.up.normalized();
  Eigen::Vector3d front = (o.front - o.front.dot(up) * up).normalized();
  Eigen::Vector3d side = up.cross(front);  // yaw turns front towards side for positive angles
  Eigen::Vector3d dir =
      std::cos(pitch) * (std::cos(yaw) * front + std::sin(yaw) * side) + std::sin(pitch) * up;
  return look_at_camera(o.target + o.distance * dir, o.target, up, o.fov_y_deg, o.width, o.height);
}

std::vector<Eigen::Vector2d> cap_angles(const CapOptions& opt) {
  if (opt.views < 1) throw std::runtime_error(fmt::format("need at least 1 view (got {})", opt.views));
  std::vector<Eigen::Vector2d> out;
  out.emplace_back(0.0, 0.0);
  const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int i = 1; i < opt.views; ++i) {
    // Low-discrepancy points in [-1, 1]^2: radius ~ sqrt(i/K) spreads them evenly over the disc,
    // then mapped to the rectangle so the extreme yaws are reached.
    double r = std::sqrt((i + 0.5) / opt.views), a = 2.0 * M_PI * golden * i;
    double x = r * std::cos(a), y = r * std::sin(a);
    double m = std::max(std::abs(x), std::abs(y));
    double scale = m > 1e-12 ? r / m : 0.0;  // disc -> square, same "radius" along each ray
    out.emplace_back(x * scale * opt.yaw_range_deg, y * scale * opt.pitch_range_deg);
  }
  return out;
}

std::vector<Camera> cap_cameras(const Orbit& orbit, const CapOptions& opt) {
  Orbit cap = orbit;
  if (opt.size > 0) cap.width = cap.height = opt.size;
  std::vector<Camera> cams;
  for (const auto& a : cap_angles(opt)) cams.push_back(orbit_camera(cap, a.x(), a.y()));
  return cams;
}

std::vector<double> sweep_yaws(int count) {
  std::vector<double> out;
  for (int i = 0; i < count; ++i)
    out.push_back(360.0 * i / count - (i * 360.0 / count > 180.0 ? 360.0 : 0.0));
  return out;
}

}  // namespace lorgnette::fit
