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

namespace {

// The directions a landmark's snap searches along: its inlier views' mean forward direction and, when
// `nearest`, the two most different of their own (the widest pair of the views that saw it, e.g. one
// from each side) and both ways square to the mean in their plane.
std::vector<Eigen::Vector3d> snap_directions(const std::vector<ViewRecord>& views,
                                             const std::vector<int>& inliers, bool nearest) {
  std::vector<Eigen::Vector3d> f;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int v : inliers) f.push_back(camera_forward(views[v].camera)), mean += f.back();
  std::vector<Eigen::Vector3d> out{mean.normalized()};
  if (!nearest) return out;
  auto farthest = [&](const Eigen::Vector3d& from) {
    return *std::min_element(f.begin(), f.end(),
                             [&](const auto& a, const auto& b) { return a.dot(from) < b.dot(from); });
  };
  const Eigen::Vector3d a = farthest(out[0]), b = farthest(a);
  for (const Eigen::Vector3d& d : {a, b})
    if (d.dot(out[0]) < 1.0 - 1e-9) out.push_back(d.normalized());
  // Square to the mean ray in the plane of the views' sweep, both ways: the nearest skin of a point
  // just inside a side of the face that the rays meet obliquely.
  const Eigen::Vector3d across = (b - a) - (b - a).dot(out[0]) * out[0];
  if (across.norm() > 1e-6) out.push_back(across.normalized()), out.push_back(-across.normalized());
  return out;
}

}  // namespace

int snap_to_surface(ViewSource& source, const std::vector<ViewRecord>& views, double reach,
                    float density_threshold, std::vector<TriangulatedPoint>& points, int skip_first,
                    int skip_last, double opacity, bool nearest) {
  int moved = 0;
  for (int k = 0; k < int(points.size()); ++k) {
    TriangulatedPoint& p = points[k];
    if (!p.ok || (k >= skip_first && k <= skip_last) || p.inliers.empty()) continue;
    // Each direction's first skin hit within +-reach of the point; the nearest one wins.
    Eigen::Vector3d best_dir = Eigen::Vector3d::Zero();
    double best_t = 0.0;
    const std::vector<Eigen::Vector3d> dirs = snap_directions(views, p.inliers, nearest);
    for (const Eigen::Vector3d& dir : dirs) {
      double t = 0.0;
      if (!first_surface_hit(source, p.position - reach * dir, dir, 0.0, 2.0 * reach, density_threshold, &t))
        continue;
      if (t <= 0.0) continue;  // already inside at the start of this search: not this way
      if (best_dir.isZero() || std::abs(t - reach) < std::abs(best_t - reach)) best_dir = dir, best_t = t;
    }
    if (best_dir.isZero()) continue;
    const Eigen::Vector3d start = p.position - reach * best_dir;
    if (opacity > 0.0 && !opacity_depth(source, start, best_dir, 0.0, 2.0 * reach, opacity, &best_t))
      continue;
    const Eigen::Vector3d snapped = start + best_t * best_dir;
    p.sigma = std::sqrt(p.sigma * p.sigma + (snapped - p.position).squaredNorm());
    p.position = snapped;
    ++moved;
  }
  return moved;
}

}  // namespace lorgnette::fit
