// Narrow views of the eyes and the limbus measured in them (see iris_views.h).
#include "fit/iris_views.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>

#include "fit/camera_math.h"
#include "fit/ray_surface.h"

namespace lorgnette::fit {

double eye_opening_ratio(const EyeContour& e) {
  const double width = (e[0] - e[3]).norm();
  if (!(width > 0.0)) return 0.0;
  return ((e[1] - e[5]).norm() + (e[2] - e[4]).norm()) / (2.0 * width);
}

namespace {

Eigen::Vector3d centre_of(const EyeContour& e) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : e) c += p;
  return c / 6.0;
}

// Where `ray` meets the head: the depth at which the render's opacity reaches a half (what the view
// shows there), searched within half the view's distance of `target`; without a surface there (a
// source without density), the point on the ray at `target`'s depth. The eye's own surface, not the
// landmarks' mean: triangulated lid landmarks sit millimetres off the eyeball, which would bias both
// the limbus' size (its depth) and the pupil's position.
Eigen::Vector3d surface_along(ViewSource& source, const Ray& ray, const Eigen::Vector3d& target,
                              double dist) {
  double t = 0.0;
  if (!opacity_depth(source, ray.origin, ray.dir, 0.5 * dist, 1.5 * dist, 0.5, &t))
    t = (target - ray.origin).dot(ray.dir);
  return ray.origin + t * ray.dir;
}

IrisMeasurement measure_eye(ViewSource& source, const Eigen::Vector3d& from, const EyeContour& eye, int side,
                            const Eigen::Vector3d& d_up, const Eigen::Vector3d& d_fwd,
                            const IrisViewOptions& o) {
  IrisMeasurement m;
  m.eye = side;
  if (const double ratio = eye_opening_ratio(eye); ratio < o.closed_ratio) {
    m.closed = true;
    m.edges.why = fmt::format("lid opening {:.3f} of the eye's width < {:.2f}", ratio, o.closed_ratio);
    return m;
  }
  const Eigen::Vector3d target = centre_of(eye);
  const double dist = (target - from).norm(), eye_width = (eye[0] - eye[3]).norm();
  const double half_w = std::atan(0.5 * o.span_eye_widths * eye_width / dist);
  const double fov_y = 2.0 * std::atan(std::tan(half_w) * o.height / o.width) * 180.0 / M_PI;
  const Camera cam = look_at_camera(from, target, d_up, fov_y, o.width, o.height);
  const Image view = source.render(cam);
  const double r0 = 0.5 * o.iris_per_eye_width * eye_width * cam.fx / dist;
  m.edges = find_iris_edges(view, Eigen::Vector2d(cam.cx, cam.cy), r0, o.edges);
  if (!m.edges.found) return m;
  // The limbus lies in a plane facing d_fwd; seen from a horizontal angle a it is cos(a) as wide.
  Eigen::Vector3d look = (from - target).normalized();
  look -= look.dot(d_up) * d_up;
  Eigen::Vector3d fwd = d_fwd - d_fwd.dot(d_up) * d_up;
  const double cosine =
      look.norm() > 1e-9 && fwd.norm() > 1e-9 ? look.normalized().dot(fwd.normalized()) : 1.0;
  m.centre = surface_along(source, camera_ray(cam, m.edges.centre_px), target, dist);
  m.diameter_units = pixels_to_units(cam, m.centre, m.edges.diameter_px) / std::max(cosine, 0.5);
  return m;
}

}  // namespace

std::vector<IrisMeasurement> measure_irises(ViewSource& source, const EyeContour& left,
                                            const EyeContour& right, const Eigen::Vector3d& d_up,
                                            const Eigen::Vector3d& d_fwd, double distance,
                                            const IrisViewOptions& o) {
  std::vector<IrisMeasurement> out;
  const Eigen::Vector3d side = d_up.cross(d_fwd).normalized();
  for (double yaw : o.yaw_deg) {
    const double a = yaw * M_PI / 180.0;
    const Eigen::Vector3d dir = std::cos(a) * d_fwd + std::sin(a) * side;
    out.push_back(measure_eye(source, centre_of(left) + distance * dir, left, +1, d_up, d_fwd, o));
    out.push_back(measure_eye(source, centre_of(right) + distance * dir, right, -1, d_up, d_fwd, o));
  }
  return out;
}

}  // namespace lorgnette::fit
