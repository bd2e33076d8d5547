// Orbit camera, capture-derived limits and row crops for banded rendering (orbit_control.h).
#include "viewer/orbit_control.h"

#include <algorithm>
#include <cmath>

namespace lorgnette::viewer {
namespace {

using render::Vec3;
constexpr double kDeg = 3.14159265358979323846 / 180.0;

Vec3 add(Vec3 a, Vec3 b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3 sub(Vec3 a, Vec3 b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 mul(Vec3 a, double s) { return {float(a[0] * s), float(a[1] * s), float(a[2] * s)}; }
double dot(Vec3 a, Vec3 b) { return double(a[0]) * b[0] + double(a[1]) * b[1] + double(a[2]) * b[2]; }
Vec3 cross(Vec3 a, Vec3 b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3 normalized(Vec3 a, Vec3 fallback) {
  double n = std::sqrt(dot(a, a));
  return n > 1e-9 ? mul(a, 1.0 / n) : fallback;
}

}  // namespace

OrbitFrame make_orbit_frame(const render::OrbitSpec& spec) {
  OrbitFrame f;
  f.center = spec.center;
  f.front = normalized(spec.front, {0, 0, 1});
  const Vec3& up = spec.up;
  Vec3 u = sub(up, mul(f.front, dot(up, f.front)));
  f.up = normalized(u, std::abs(f.front[1]) < 0.9f ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
  if (std::abs(dot(f.up, f.front)) > 0.5)
    f.up = normalized(sub(f.up, mul(f.front, dot(f.up, f.front))), {1, 0, 0});
  f.right = normalized(cross(f.up, f.front), {1, 0, 0});
  f.radius = float(std::sqrt(dot(spec.half_extent, spec.half_extent)));
  f.fov_y_deg = spec.fov_y_deg;
  f.margin = spec.margin;
  return f;
}

OrbitLimits limits_from_range(const std::optional<nerf::ViewRange>& range, double margin_deg,
                              double min_span_deg) {
  OrbitLimits l;
  if (!range) return l;
  double ymin = range->yaw_min, ymax = range->yaw_max, pmin = range->pitch_min, pmax = range->pitch_max;
  auto widen = [&](double& lo, double& hi, double bound) {
    lo -= margin_deg, hi += margin_deg;
    if (hi - lo < min_span_deg) {
      double mid = 0.5 * (lo + hi);
      lo = mid - 0.5 * min_span_deg, hi = mid + 0.5 * min_span_deg;
    }
    lo = std::max(lo, -bound), hi = std::min(hi, bound);
  };
  widen(ymin, ymax, 180.0);
  widen(pmin, pmax, 80.0);
  // The start view (yaw 0, pitch 0) is the capture's mean direction: always inside.
  l.yaw_min = std::min(ymin, 0.0), l.yaw_max = std::max(ymax, 0.0);
  l.pitch_min = std::min(pmin, 0.0), l.pitch_max = std::max(pmax, 0.0);
  l.source = "capture (" + std::to_string(range->cameras) + " cameras)";
  return l;
}

OrbitState clamp_orbit(const OrbitState& s, const OrbitLimits& l) {
  OrbitState o = s;
  o.yaw_deg = std::clamp(s.yaw_deg, l.yaw_min, l.yaw_max);
  o.pitch_deg = std::clamp(s.pitch_deg, l.pitch_min, l.pitch_max);
  o.distance = std::clamp(s.distance, l.distance_min, l.distance_max);
  o.pan_x = std::clamp(s.pan_x, -l.pan_max, l.pan_max);
  o.pan_y = std::clamp(s.pan_y, -l.pan_max, l.pan_max);
  return o;
}

Camera orbit_camera(const OrbitFrame& f, const OrbitState& s, uint32_t width, uint32_t height) {
  double yaw = s.yaw_deg * kDeg, pitch = s.pitch_deg * kDeg;
  Vec3 dir = add(add(mul(f.right, std::cos(pitch) * std::sin(yaw)), mul(f.up, std::sin(pitch))),
                 mul(f.front, std::cos(pitch) * std::cos(yaw)));
  float dist = render::framing_distance(f.radius, f.fov_y_deg, width, height, f.margin) * float(s.distance);
  // Pan is a fraction of the radius along the orbit's right and up axes.
  Vec3 target = add(f.center, add(mul(f.right, s.pan_x * f.radius), mul(f.up, s.pan_y * f.radius)));
  return render::look_at(add(target, mul(dir, dist)), target, f.up, width, height, f.fov_y_deg);
}

Camera crop_rows(const Camera& cam, uint32_t y0, uint32_t rows) {
  Camera c = cam;
  c.cy = cam.cy - float(y0);
  c.height = rows;
  return c;
}

nlohmann::json to_json(const OrbitLimits& l) {
  return {{"yaw", {l.yaw_min, l.yaw_max}},
          {"pitch", {l.pitch_min, l.pitch_max}},
          {"distance", {l.distance_min, l.distance_max}},
          {"pan", l.pan_max},
          {"source", l.source}};
}

}  // namespace lorgnette::viewer
