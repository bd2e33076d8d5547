// Surface casting of silhouette landmarks (see surface_landmarks.h).
#include "fit/surface_landmarks.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "fit/camera_math.h"
#include "fit/detect_views.h"
#include "fit/front_search.h"
#include "fit/ray_surface.h"

namespace lorgnette::fit {

Eigen::Vector3d component_median(std::vector<Eigen::Vector3d> v) {
  if (v.empty()) throw std::invalid_argument("component_median of no points");
  Eigen::Vector3d m;
  std::vector<double> x(v.size());
  for (int c = 0; c < 3; ++c) {
    for (size_t i = 0; i < v.size(); ++i) x[i] = v[i][c];
    std::nth_element(x.begin(), x.begin() + x.size() / 2, x.end());
    m[c] = x[x.size() / 2];
  }
  return m;
}

bool contour_side_visible(int k, const FaceDetection& detection, double tolerance) {
  if (k < 0 || k > 16 || k == 8) return true;
  const double a = face_asymmetry(detection);  // > 0: the subject's right half is the wider
  return k < 8 ? a >= -tolerance : a <= tolerance;
}

void cast_surface_landmarks(ViewSource& source, const std::vector<ViewRecord>& views, const Orbit& orbit,
                            const SurfaceCastOptions& opt, float density_threshold,
                            std::vector<TriangulatedPoint>& points) {
  const double t0 = opt.near * orbit.distance, t1 = opt.far * orbit.distance;
  std::vector<size_t> in_range;  // views with a face within max_yaw_deg
  for (size_t v = 0; v < views.size(); ++v)
    if (views[v].detection.found && std::abs(views[v].yaw_deg) <= opt.max_yaw_deg) in_range.push_back(v);
  for (int k = opt.first; k <= opt.last && k < int(points.size()); ++k) {
    std::vector<size_t> usable;
    for (size_t v : in_range)
      if (contour_side_visible(k, views[v].detection, opt.side_tolerance)) usable.push_back(v);
    if (usable.empty()) usable = in_range;
    std::vector<Eigen::Vector3d> hits;
    std::vector<int> used;
    for (size_t v : usable) {
      Ray r = camera_ray(views[v].camera, views[v].detection.points[k]);
      double t = 0.0;
      const bool hit = opt.opacity > 0.0
                           ? opacity_depth(source, r.origin, r.dir, t0, t1, opt.opacity, &t)
                           : first_surface_hit(source, r.origin, r.dir, t0, t1, density_threshold, &t);
      if (hit) hits.push_back(r.origin + t * r.dir), used.push_back(int(v));
    }
    if (hits.empty()) continue;
    TriangulatedPoint p;
    p.position = component_median(hits);
    p.ok = true;
    p.inliers = used;
    p.reprojection_px.assign(views.size(), -1.0);
    double d2 = 0.0, px2 = 0.0;
    for (size_t i = 0; i < hits.size(); ++i) {
      d2 += (hits[i] - p.position).squaredNorm();
      Eigen::Vector2d uv;
      const ViewRecord& view = views[used[i]];
      double e = camera_project(view.camera, p.position, &uv) ? (uv - view.detection.points[k]).norm() : 1e9;
      p.reprojection_px[used[i]] = e;
      px2 += e * e;
    }
    p.rms_ray_distance = std::sqrt(d2 / hits.size());
    p.sigma = p.rms_ray_distance;  // spread of the per-view surface points
    p.covariance = Eigen::Matrix3d::Identity() * (p.sigma * p.sigma / 3.0);
    p.rms_reprojection_px = std::sqrt(px2 / hits.size());
    points[k] = p;
  }
}

int snap_to_surface(ViewSource& source, const std::vector<ViewRecord>& views, double reach,
                    float density_threshold, std::vector<TriangulatedPoint>& points, int skip_first,
                    int skip_last, double opacity) {
  int moved = 0;
  for (int k = 0; k < int(points.size()); ++k) {
    TriangulatedPoint& p = points[k];
    if (!p.ok || (k >= skip_first && k <= skip_last) || p.inliers.empty()) continue;
    Eigen::Vector3d dir = Eigen::Vector3d::Zero();
    for (int v : p.inliers) dir += camera_forward(views[v].camera);
    dir.normalize();
    double t = 0.0;
    const Eigen::Vector3d start = p.position - reach * dir;
    if (!first_surface_hit(source, start, dir, 0.0, 2.0 * reach, density_threshold, &t)) continue;
    if (t <= 0.0) continue;  // already inside at the start of the search: leave it
    if (opacity > 0.0 && !opacity_depth(source, start, dir, 0.0, 2.0 * reach, opacity, &t)) continue;
    Eigen::Vector3d snapped = p.position - reach * dir + t * dir;
    p.sigma = std::sqrt(p.sigma * p.sigma + (snapped - p.position).squaredNorm());
    p.position = snapped;
    ++moved;
  }
  return moved;
}

}  // namespace lorgnette::fit
