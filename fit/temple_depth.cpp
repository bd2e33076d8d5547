// The temples at one depth (see temple_depth.h).
#include "fit/temple_depth.h"

#include <fmt/format.h>

#include <cmath>

#include "fit/camera_math.h"
#include "fit/detect_views.h"
#include "fit/landmark_ids.h"
#include "fit/surface_landmarks.h"

namespace lorgnette::fit {

std::string TempleDepthResult::summary() const {
  if (moved == 0) return fmt::format("temples {:.1f} mm apart in depth: kept", std::abs(gap_mm));
  return fmt::format(
      "the {} temple lay {:.1f} mm behind the {} one (a soft surface where the capture saw that side of "
      "the head at grazing angles): moved forward to its depth along {} of its rays",
      moved > 0 ? "left" : "right", std::abs(gap_mm), moved > 0 ? "right" : "left", rays);
}

TempleDepthResult balance_temple_depths(const std::vector<ViewRecord>& views, const HeadFrame& head,
                                        const TempleDepthOptions& opt,
                                        std::vector<TriangulatedPoint>& points) {
  TempleDepthResult out;
  if (points.size() <= size_t(lm::kTempleL)) return out;
  TriangulatedPoint& left = points[lm::kTempleL];
  TriangulatedPoint& right = points[lm::kTempleR];
  if (!left.ok || !right.ok || !(head.mm_per_unit > 0.0)) return out;
  const Eigen::Vector3d fwd = head.d_fwd.normalized();
  const double z_l = left.position.dot(fwd), z_r = right.position.dot(fwd);
  out.gap_mm = (z_l - z_r) * head.mm_per_unit;
  if (!opt.enabled || std::abs(out.gap_mm) <= opt.max_gap_mm) return out;
  const int side = out.gap_mm < 0.0 ? +1 : -1;  // the one behind
  TriangulatedPoint& back = side > 0 ? left : right;
  const int k = side > 0 ? lm::kTempleL : lm::kTempleR;
  const double z = side > 0 ? z_r : z_l;
  std::vector<Eigen::Vector3d> hits;
  for (int v : back.inliers) {
    if (v < 0 || size_t(v) >= views.size() || !views[v].detection.found) continue;
    const Ray r = camera_ray(views[v].camera, views[v].detection.points[k]);
    const double along = r.dir.dot(fwd);
    if (std::abs(along) < 0.2) continue;  // a ray nearly across d_fwd does not fix a depth
    const double t = (z - r.origin.dot(fwd)) / along;
    if (t > 0.0) hits.push_back(r.origin + t * r.dir);
  }
  if (hits.empty()) return out;
  const Eigen::Vector3d moved_to = component_median(hits);
  back.sigma = std::sqrt(back.sigma * back.sigma + (moved_to - back.position).squaredNorm());
  back.position = moved_to;
  out.moved = side;
  out.rays = int(hits.size());
  return out;
}

}  // namespace lorgnette::fit
