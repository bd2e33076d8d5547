// Front sweep and face framing (see front_search.h).
#include "fit/front_search.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "fit/camera_math.h"
#include "fit/landmark_ids.h"
#include "fit/ray_surface.h"

namespace lorgnette::fit {

double face_asymmetry(const FaceDetection& d) {
  if (d.points.size() != 68) return 1.0;
  double a = std::abs(d.points[lm::kNoseTip].x() - d.points[lm::kTempleR].x());
  double b = std::abs(d.points[lm::kTempleL].x() - d.points[lm::kNoseTip].x());
  return (a + b) > 0 ? (a - b) / (a + b) : 1.0;
}

namespace {

Orbit initial_orbit(ViewSource& source, const FrontSearchOptions& opt) {
  Bounds b = source.bounds();
  ViewPrior prior = source.prior();
  Orbit o;
  o.up = prior.up.normalized();
  o.target = prior.target ? *prior.target : b.center().cast<double>();
  Eigen::Vector3d front = prior.front ? *prior.front : Eigen::Vector3d(0, 0, 1);
  front -= front.dot(o.up) * o.up;
  if (front.norm() < 1e-6) front = o.up.unitOrthogonal();
  o.front = front.normalized();
  double radius = 0.5 * b.size().cast<double>().norm();
  o.fov_y_deg = opt.fov_y_deg;
  o.distance = 1.05 * radius / std::sin(0.5 * opt.fov_y_deg * M_PI / 180.0);
  o.width = opt.width;
  o.height = opt.height;
  return o;
}

}  // namespace

FrontSearchResult find_front(ViewSource& source, const LandmarkDetector& detector,
                             const FrontSearchOptions& opt, float density_threshold) {
  FrontSearchResult res;
  Orbit o = initial_orbit(source, opt);
  std::vector<double> yaws = source.prior().front ? std::vector<double>{0.0} : sweep_yaws(opt.sweep_views);
  int best = -1;
  FaceDetection best_det;
  Camera best_cam{};
  // Renders and detects one yaw on `orbit`, keeping the most frontal face seen so far.
  auto try_view = [&](const Orbit& orbit, double yaw) {
    Camera cam = orbit_camera(orbit, yaw, 0.0);
    FaceDetection d = detector.detect(source.render(cam));
    res.tried_yaws.push_back(yaw);
    res.found.push_back(d.found);
    if (d.found && (best < 0 || std::abs(face_asymmetry(d)) < std::abs(face_asymmetry(best_det)))) {
      best = int(res.tried_yaws.size()) - 1;
      best_det = d;
      best_cam = cam;
    }
    return d;
  };
  for (size_t pass = 0; pass < 2 && best < 0; ++pass) {
    if (pass == 1) {
      if (!source.prior().front) break;
      yaws = sweep_yaws(opt.sweep_views);  // the prior's front showed no face: sweep after all
      yaws.erase(yaws.begin());
    }
    for (double yaw : yaws) try_view(o, yaw);
  }
  // Secant refinement of the yaw on the signed asymmetry (it grows with yaw through the front).
  Orbit probe = o;  // smaller renders: the asymmetry does not depend on the image size
  if (opt.refine_size > 0) {
    probe.width = std::min(o.width, opt.refine_size);
    probe.height = std::min(o.height, opt.refine_size);
  }
  if (best >= 0) {
    double y0 = res.tried_yaws[best], a0 = face_asymmetry(best_det);
    double y1 = y0 - 40.0 * a0;  // first guess: asymmetry ~ yaw / 40 deg, sign found by the probe
    for (int k = 0; k < opt.refine_views && std::abs(face_asymmetry(best_det)) > opt.asymmetry_tolerance;
         ++k) {
      y1 = std::clamp(y1, y0 - 45.0, y0 + 45.0);
      FaceDetection d = try_view(probe, y1);
      if (!d.found) break;
      double a1 = face_asymmetry(d);
      if (std::abs(a1 - a0) < 1e-6) break;
      double next = y1 - a1 * (y1 - y0) / (a1 - a0);
      y0 = y1, a0 = a1, y1 = next;
    }
  }
  if (best < 0)
    throw std::runtime_error(fmt::format(
        "no face found in any of the {} front-search views (yaws {} deg about the scene's up axis, "
        "{}x{} px): check that the model shows a head, that up is right, or raise the resolution",
        res.tried_yaws.size(), fmt::join(res.tried_yaws, ", "), opt.width, opt.height));
  // Frame the face: box centre ray, surface depth, face width in scene units.
  Eigen::Vector2d centre(0.5 * (best_det.box[0] + best_det.box[2]),
                         0.5 * (best_det.box[1] + best_det.box[3]));
  Ray ray = camera_ray(best_cam, centre);
  double t = o.distance;
  double radius = 0.5 * source.bounds().size().cast<double>().norm();
  if (!first_surface_hit(source, ray.origin, ray.dir, std::max(0.0, o.distance - radius), o.distance + radius,
                         density_threshold, &t))
    spdlog::warn("fit: no surface behind the detected face box; framing on the bounds centre");
  double face_w = (best_det.box[2] - best_det.box[0]) * t / best_cam.fx;
  Orbit framed = o;
  framed.target = ray.origin + (t + 0.5 * face_w) * ray.dir;
  Eigen::Vector3d f = -ray.dir - (-ray.dir).dot(o.up) * o.up;
  framed.front = f.normalized();
  double view_w = face_w / opt.face_fraction;
  framed.distance = 0.5 * view_w / std::tan(0.5 * opt.fov_y_deg * M_PI / 180.0) + 0.5 * face_w;
  res.orbit = framed;
  res.surface_distance = t;
  spdlog::info(
      "fit: front at yaw {:.0f} deg (asymmetry {:.2f}), face {:.3f} units wide, orbit distance {:.3f}",
      res.tried_yaws[best], face_asymmetry(best_det), face_w, framed.distance);
  return res;
}

}  // namespace lorgnette::fit
