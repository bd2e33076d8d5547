// The fit's input checks and its verdict's tolerances; see input_checks.h.
#include "fit/input_checks.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

namespace lorgnette::fit {
namespace {

constexpr int kInnerFirst = 17, kCount = 68;
constexpr int kPlacementLandmarks[] = {27, 28, 36, 39, 42, 45};  // nose bridge, eye corners
constexpr size_t kRaysPerLandmark = 3;
constexpr double kSampleMm = 0.5;  // sample spacing along a landmark's ray

constexpr const char* kRefilm =
    "the head was reconstructed with holes there. Film again with a metre or more between you and the "
    "wall, your face lit from the front, turning slowly from one ear to the other";

bool placement_landmark(int k) {
  return std::find(std::begin(kPlacementLandmarks), std::end(kPlacementLandmarks), k) !=
         std::end(kPlacementLandmarks);
}

// Samples along the ray from `origin` through `p`, `reach` scene units either side of p.
void ray_samples(const Eigen::Vector3d& origin, const Eigen::Vector3d& p, double reach, double step,
                 std::vector<Eigen::Vector3f>& samples) {
  const Eigen::Vector3d dir = (p - origin).normalized();
  for (double t = -reach + 0.5 * step; t < reach; t += step) samples.push_back((p + t * dir).cast<float>());
}

}  // namespace

InputCheck check_nose_skin(const ColourFn& colour, const std::vector<Eigen::Vector3d>& nose_line,
                           const Eigen::Vector3d& view_dir) {
  InputCheck c;
  c.name = "nose_skin";
  c.limit = kMinSkinLuminance;
  if (!colour || nose_line.empty()) return c;
  std::vector<Eigen::Vector3f> p, d;
  for (const auto& q : nose_line)
    p.push_back(q.cast<float>()), d.push_back(view_dir.normalized().cast<float>());
  const std::vector<Eigen::Vector3f> rgb = colour(p, d);
  if (rgb.size() != p.size()) return c;  // a source without colour (a mesh)
  std::vector<double> lum;
  for (const auto& v : rgb) lum.push_back(std::isfinite(luminance(v)) ? luminance(v) : 0.0);
  std::sort(lum.begin(), lum.end());
  c.checked = true;
  c.value = lum[(lum.size() - 1) / 2];  // the lower median, as hair.h reads the skin
  c.passed = c.value >= kMinSkinLuminance;
  if (!c.passed)
    c.reason = fmt::format(
        "the nose line reads no skin (linear luminance {:.4f}, under {:.4f}, darker than any lit skin): {}",
        c.value, kMinSkinLuminance, kRefilm);
  return c;
}

InputCheck check_landmarks_solid(const DensityFn& density, const std::vector<Camera>& cameras,
                                 const std::vector<TriangulatedPoint>& points, double mm_per_unit) {
  InputCheck c;
  c.name = "landmarks_solid";
  c.limit = kEmptyLandmarkShare;
  if (!density || !(mm_per_unit > 0.0) || points.size() != size_t(kCount)) return c;
  const double reach = kSolidReachMm / mm_per_unit, step = kSampleMm / mm_per_unit;
  // Every ray's samples in one density query (a NeRF answers in batches on the device).
  std::vector<Eigen::Vector3f> samples;
  std::vector<int> ray_landmark;
  for (int k = kInnerFirst; k < kCount; ++k) {
    const TriangulatedPoint& p = points[size_t(k)];
    const size_t n = std::min(kRaysPerLandmark, p.inliers.size());
    if (!p.ok) continue;
    for (size_t i = 0; i < n; ++i) {
      const size_t v = size_t(p.inliers[i * p.inliers.size() / n]);
      if (v >= cameras.size()) continue;
      const LgnVec3 o = camera_origin(&cameras[v]);
      ray_samples({o.x, o.y, o.z}, p.position, reach, step, samples);
      ray_landmark.push_back(k);
    }
  }
  if (ray_landmark.empty()) return c;
  const std::vector<float> sigma = density(samples);
  if (sigma.size() != samples.size()) return c;
  const size_t per_ray = samples.size() / ray_landmark.size();
  std::vector<double> opacity(kCount, -1.0);  // the largest over the landmark's rays
  for (size_t r = 0; r < ray_landmark.size(); ++r) {
    double depth = 0.0;
    for (size_t i = r * per_ray; i < (r + 1) * per_ray; ++i)
      depth += std::isfinite(sigma[i]) ? std::max(0.0f, sigma[i]) * step : 0.0;
    double& o = opacity[size_t(ray_landmark[r])];
    o = std::max(o, 1.0 - std::exp(-depth));
  }
  std::vector<int> empty;
  int judged = 0;
  bool anchor_empty = false;
  for (int k = kInnerFirst; k < kCount; ++k) {
    if (opacity[size_t(k)] < 0.0) continue;
    ++judged;
    if (opacity[size_t(k)] >= kLandmarkOpacity) continue;
    empty.push_back(k);
    anchor_empty = anchor_empty || placement_landmark(k);
  }
  c.checked = true;
  c.value = double(empty.size()) / double(judged);
  c.passed = !anchor_empty && c.value < kEmptyLandmarkShare;
  if (!c.passed)
    c.reason = fmt::format(
        "{} of {} face landmarks lie in empty space (opacity under {:.1f} within {:.0f} mm of them along "
        "their rays: dlib {}{}): {}",
        empty.size(), judged, kLandmarkOpacity, kSolidReachMm, fmt::join(empty, " "),
        anchor_empty ? ", among them the nose bridge or an eye corner the frame is placed by" : "", kRefilm);
  return c;
}

InputCheck check_temple_spread(const TempleFitResult& t, bool ears_estimated) {
  InputCheck c;
  c.name = "temple_spread";
  c.limit = kMaxWornSpreadDeg;
  if (!t.fitted) return c;
  c.checked = true;
  c.value = std::max(t.left.spread_deg, t.right.spread_deg);
  c.passed = c.value <= kMaxWornSpreadDeg;
  if (!c.passed)
    c.reason = fmt::format(
        "the temples would have to spread {:.2f} / {:.2f} deg (left / right) to clear the head, more than "
        "the {:.0f} deg a worn frame bends: the head is wider there than any head, so what the temples "
        "meet is not where a worn temple rests: {}. Film again with the ears in view, turning from one ear "
        "to the other, with your own glasses off and the hair behind the ears",
        t.left.spread_deg, t.right.spread_deg, kMaxWornSpreadDeg,
        ears_estimated ? "the ears' rests were not found on the head, and a temple turned onto the "
                         "estimate (20-40 mm behind the ear) passes through the ear itself, or haze beside it"
                       : "haze beside the head");
  return c;
}

InputCheck check_front_penetration(bool refined, double front_penetration_mm, double tolerance_mm) {
  InputCheck c;
  c.name = "front_penetration";
  c.limit = tolerance_mm;
  if (!refined) return c;
  c.checked = true;
  c.value = front_penetration_mm;
  c.passed = front_penetration_mm <= tolerance_mm;
  if (!c.passed)
    c.reason = fmt::format(
        "the front of the frame still penetrates the face by {:.2f} mm (tolerance {:.2f} mm: the NeRF's "
        "skin and the skin under the pads)",
        front_penetration_mm, tolerance_mm);
  return c;
}

}  // namespace lorgnette::fit
