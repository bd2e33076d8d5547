// The temples at one depth (see temple_depth.h).
#include "fit/temple_depth.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "fit/camera_math.h"
#include "fit/detect_views.h"
#include "fit/landmark_ids.h"
#include "fit/ray_surface.h"
#include "fit/surface_landmarks.h"

namespace lorgnette::fit {

std::string TempleDepthResult::summary() const {
  const std::string skin = fmt::format(
      "casts {:.1f} / {:.1f} mm off the skin seen from the side, left / right", off_skin_l_mm, off_skin_r_mm);
  if (moved == 0) return fmt::format("temples {:.1f} mm apart in depth ({}): kept", std::abs(gap_mm), skin);
  const bool left = moved > 0;
  const bool forward = left ? gap_mm < 0.0 : gap_mm > 0.0;
  return fmt::format(
      "the {} temple lay {:.1f} mm {} the {} one ({}): moved {} to its depth along {} of its rays",
      left ? "left" : "right", std::abs(gap_mm), forward ? "behind" : "in front of", left ? "right" : "left",
      skin, forward ? "forward" : "back", rays);
}

double off_skin_mm(ViewSource& source, const HeadFrame& head, const Eigen::Vector3d& point, int side,
                   double probe_mm) {
  const double reach = probe_mm / head.mm_per_unit;
  const Eigen::Vector3d out = double(side) * head.d_eye.normalized();
  double t = 0.0;
  if (!opacity_depth(source, point + reach * out, -out, 0.0, 2.0 * reach, 0.5, &t))
    return std::numeric_limits<double>::infinity();
  return std::abs(t - reach) * head.mm_per_unit;
}

namespace {

// Moves temple k along its inlier views' rays to depth z along `fwd` (the rays' median point there).
int move_to_depth(const std::vector<ViewRecord>& views, int k, const Eigen::Vector3d& fwd, double z,
                  TriangulatedPoint& p) {
  std::vector<Eigen::Vector3d> hits;
  for (int v : p.inliers) {
    if (v < 0 || size_t(v) >= views.size() || !views[v].detection.found) continue;
    const Ray r = camera_ray(views[v].camera, views[v].detection.points[k]);
    const double along = r.dir.dot(fwd);
    if (std::abs(along) < 0.2) continue;  // a ray nearly across d_fwd does not fix a depth
    const double t = (z - r.origin.dot(fwd)) / along;
    if (t > 0.0) hits.push_back(r.origin + t * r.dir);
  }
  if (hits.empty()) return 0;
  const Eigen::Vector3d moved_to = component_median(hits);
  p.sigma = std::sqrt(p.sigma * p.sigma + (moved_to - p.position).squaredNorm());
  p.position = moved_to;
  return int(hits.size());
}

}  // namespace

TempleDepthResult balance_temple_depths(ViewSource& source, const std::vector<ViewRecord>& views,
                                        const HeadFrame& head, const TempleDepthOptions& opt,
                                        std::vector<TriangulatedPoint>& points) {
  TempleDepthResult out;
  if (points.size() <= size_t(lm::kTempleL)) return out;
  TriangulatedPoint& left = points[lm::kTempleL];
  TriangulatedPoint& right = points[lm::kTempleR];
  if (!left.ok || !right.ok || !(head.mm_per_unit > 0.0)) return out;
  const Eigen::Vector3d fwd = head.d_fwd.normalized();
  out.gap_mm = (left.position - right.position).dot(fwd) * head.mm_per_unit;
  if (!opt.enabled) return out;
  // Read whatever the gap (two rays), so that the log shows how far good casts lie off the skin.
  out.off_skin_l_mm = off_skin_mm(source, head, left.position, +1, opt.probe_mm);
  out.off_skin_r_mm = off_skin_mm(source, head, right.position, -1, opt.probe_mm);
  if (std::abs(out.gap_mm) <= opt.max_gap_mm) return out;
  if (out.off_skin_l_mm == out.off_skin_r_mm) return out;            // no side is better supported
  const int side = out.off_skin_l_mm > out.off_skin_r_mm ? +1 : -1;  // the one further off the skin
  const TriangulatedPoint& ref = side > 0 ? right : left;
  out.rays = move_to_depth(views, side > 0 ? lm::kTempleL : lm::kTempleR, fwd, ref.position.dot(fwd),
                           side > 0 ? left : right);
  if (out.rays > 0) out.moved = side;
  return out;
}

}  // namespace lorgnette::fit
