// Look-at and orbit cameras: see orbit.h.
#include "host/render/orbit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lorgnette::render {
namespace {
constexpr float kPi = 3.14159265358979f;
Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
float dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 normalized(const Vec3& a, const char* what) {
  float n = std::sqrt(dot(a, a));
  if (!(n > 1e-12f) || !std::isfinite(n))
    throw std::invalid_argument(std::string("camera: ") + what + " is zero or not finite");
  return {a[0] / n, a[1] / n, a[2] / n};
}
// Rotation of v about the unit axis k by angle a (Rodrigues).
Vec3 rotate(const Vec3& v, const Vec3& k, float a) {
  Vec3 kxv = cross(k, v);
  float c = std::cos(a), s = std::sin(a), kd = dot(k, v) * (1 - c);
  return {v[0] * c + kxv[0] * s + k[0] * kd, v[1] * c + kxv[1] * s + k[1] * kd,
          v[2] * c + kxv[2] * s + k[2] * kd};
}
}  // namespace

Camera look_at(const Vec3& eye, const Vec3& target, const Vec3& up, uint32_t width, uint32_t height,
               float fov_y_deg) {
  if (width == 0 || height == 0) throw std::invalid_argument("camera: image size must be positive");
  if (!(fov_y_deg > 0.0f && fov_y_deg < 179.0f))
    throw std::invalid_argument("camera: vertical field of view must be in (0, 179) degrees");
  Vec3 back = normalized(sub(eye, target), "eye - target");
  normalized(cross(up, back), "up x view direction (up parallel to the view?)");  // throws when degenerate
  return camera_look_at(lgn_vec3(eye[0], eye[1], eye[2]), lgn_vec3(target[0], target[1], target[2]),
                        lgn_vec3(up[0], up[1], up[2]), fov_y_deg, width, height);
}

float framing_distance(float radius, float fov_y_deg, uint32_t width, uint32_t height, float margin) {
  float half_y = 0.5f * fov_y_deg * kPi / 180.0f;
  float half_x = std::atan(std::tan(half_y) * float(width) / float(height));
  float half = std::min(half_x, half_y);
  return margin * radius / std::sin(half);
}

float orbit_yaw_deg(const OrbitSpec& s, uint32_t i) {
  float t = float(i) / float(std::max(s.views, 1u));
  if (s.yaw_max_deg - s.yaw_min_deg >= 359.999f) return s.yaw_start_deg + 360.0f * t;
  // Start (clamped into the arc) -> max -> min -> start at constant angular speed.
  float lo = s.yaw_min_deg, hi = s.yaw_max_deg, start = std::clamp(s.yaw_start_deg, lo, hi);
  float d = t * 2.0f * (hi - lo);
  if (d <= hi - start) return start + d;
  d -= hi - start;
  if (d <= hi - lo) return hi - d;
  return lo + (d - (hi - lo));
}

std::vector<Camera> orbit_cameras(const OrbitSpec& s) {
  if (s.views == 0) throw std::invalid_argument("orbit: at least one view is needed");
  if (!(s.yaw_min_deg <= s.yaw_max_deg) || s.yaw_min_deg < -180.0f || s.yaw_max_deg > 180.0f)
    throw std::invalid_argument("orbit: the azimuth arc must satisfy -180 <= min <= max <= 180 degrees");
  Vec3 up = normalized(s.up, "orbit up vector");
  Vec3 front = normalized(s.front, "orbit front vector");
  // Elevation tilts the front towards `up` about the horizontal axis.
  Vec3 side = normalized(cross(up, front), "up x front (front parallel to up?)");
  Vec3 dir0 = rotate(front, side, -s.elevation_deg * kPi / 180.0f);
  float radius = std::sqrt(dot(s.half_extent, s.half_extent));
  float dist = framing_distance(radius, s.fov_y_deg, s.width, s.height, s.margin);
  std::vector<Camera> cams;
  for (uint32_t i = 0; i < s.views; ++i) {
    Vec3 d = rotate(dir0, up, orbit_yaw_deg(s, i) * kPi / 180.0f);
    Vec3 eye = {s.center[0] + dist * d[0], s.center[1] + dist * d[1], s.center[2] + dist * d[2]};
    cams.push_back(look_at(eye, s.center, up, s.width, s.height, s.fov_y_deg));
  }
  return cams;
}

namespace {
Vec3 mean_axis(const std::vector<Camera>& cams, int column, const Vec3& fallback) {
  Vec3 m{0, 0, 0};
  for (const Camera& c : cams)
    for (int r = 0; r < 3; ++r) m[r] += c.c2w[4 * r + column];
  float n = std::sqrt(dot(m, m));
  if (!(n > 1e-3f * float(cams.size())) || !std::isfinite(n)) return fallback;
  return {m[0] / n, m[1] / n, m[2] / n};
}
}  // namespace

Vec3 front_from_cameras(const std::vector<Camera>& cams) { return mean_axis(cams, 2, {0, 0, 1}); }
Vec3 up_from_cameras(const std::vector<Camera>& cams) { return mean_axis(cams, 1, {0, 1, 0}); }

}  // namespace lorgnette::render
