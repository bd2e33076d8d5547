// The capture's view range (see view_range.h).
#include "host/nerf/view_range.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lorgnette::nerf {
namespace {

using V = std::array<double, 3>;
constexpr double kDeg = 3.14159265358979323846 / 180.0;

V vd(const std::array<float, 3>& a) { return {a[0], a[1], a[2]}; }
std::array<float, 3> vf(const V& a) { return {float(a[0]), float(a[1]), float(a[2])}; }
double dot(const V& a, const V& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V sub(const V& a, const V& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V axpy(double s, const V& a, const V& b) { return {s * a[0] + b[0], s * a[1] + b[1], s * a[2] + b[2]}; }
V cross(const V& a, const V& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const V& a) { return std::sqrt(dot(a, a)); }
// a / |a|, or {0,0,0} when |a| is (numerically) zero.
V unit(const V& a) {
  double n = norm(a);
  return n > 1e-9 && std::isfinite(n) ? V{a[0] / n, a[1] / n, a[2] / n} : V{0, 0, 0};
}
V column(const Camera& c, int k) { return {c.c2w[k], c.c2w[4 + k], c.c2w[8 + k]}; }
// The component of v orthogonal to the unit vector u, normalised (zero when v is parallel to u).
V horizontal(const V& v, const V& u) { return unit(axpy(-dot(v, u), u, v)); }

}  // namespace

bool ViewRange::valid() const {
  V f = vd(front), u = vd(up);
  for (double v : {yaw_min, yaw_max, pitch_min, pitch_max, f[0], f[1], f[2], u[0], u[1], u[2],
                   double(center[0]), double(center[1]), double(center[2])})
    if (!std::isfinite(v)) return false;
  return std::abs(norm(f) - 1) < 1e-3 && std::abs(norm(u) - 1) < 1e-3 && std::abs(dot(f, u)) < 1e-3 &&
         -180 <= yaw_min && yaw_min <= yaw_max && yaw_max <= 180 && -90 <= pitch_min &&
         pitch_min <= pitch_max && pitch_max <= 90;
}

ViewRange ViewRange::widened(double margin) const {
  ViewRange r = *this;
  r.yaw_min = std::max(-180.0, yaw_min - margin), r.yaw_max = std::min(180.0, yaw_max + margin);
  r.pitch_min = std::max(-89.0, pitch_min - margin), r.pitch_max = std::min(89.0, pitch_max + margin);
  return r;
}

std::string ViewRange::summary() const {
  return fmt::format("yaw {:+.0f}..{:+.0f} deg, pitch {:+.0f}..{:+.0f} deg ({} cameras)", yaw_min, yaw_max,
                     pitch_min, pitch_max, cameras);
}

ViewRange view_range_from_cameras(const std::vector<Camera>& cameras, const std::array<float, 3>& center) {
  if (cameras.empty()) throw std::invalid_argument("view range: no cameras");
  V up_sum{0, 0, 0}, back_sum{0, 0, 0};
  for (const Camera& c : cameras)
    up_sum = axpy(1, column(c, 1), up_sum), back_sum = axpy(1, column(c, 2), back_sum);
  V up = unit(up_sum);
  if (norm(up) == 0) up = {0, 1, 0};  // cameras rolled every way: the dataset's +y
  V front = horizontal(back_sum, up);
  // Cameras all round the subject (or straight above it) have no mean direction: start anywhere.
  for (size_t i = 0; norm(front) == 0 && i < cameras.size(); ++i)
    front = horizontal(column(cameras[i], 2), up);
  if (norm(front) == 0) front = horizontal({0, 0, 1}, up);
  if (norm(front) == 0) front = horizontal({1, 0, 0}, up);
  ViewRange r;
  r.center = center;
  r.up = vf(up);
  r.front = vf(front);
  r.cameras = static_cast<uint32_t>(cameras.size());
  r.yaw_min = r.pitch_min = 1e9, r.yaw_max = r.pitch_max = -1e9;
  for (const Camera& c : cameras) {
    auto yp = yaw_pitch_of(r, {c.c2w[3], c.c2w[7], c.c2w[11]});
    r.yaw_min = std::min(r.yaw_min, yp[0]), r.yaw_max = std::max(r.yaw_max, yp[0]);
    r.pitch_min = std::min(r.pitch_min, yp[1]), r.pitch_max = std::max(r.pitch_max, yp[1]);
  }
  return r;
}

std::array<double, 2> yaw_pitch_of(const ViewRange& r, const std::array<float, 3>& position) {
  V d = unit(sub(vd(position), vd(r.center)));
  if (norm(d) == 0) return {0, 0};
  V up = vd(r.up), front = vd(r.front), right = cross(up, front);
  double yaw = std::atan2(dot(d, right), dot(d, front)) / kDeg;
  double pitch = std::asin(std::clamp(dot(d, up), -1.0, 1.0)) / kDeg;
  return {yaw, pitch};
}

std::array<float, 3> direction_at(const ViewRange& r, double yaw_deg, double pitch_deg) {
  V up = vd(r.up), front = vd(r.front), right = cross(up, front);
  double cy = std::cos(yaw_deg * kDeg), sy = std::sin(yaw_deg * kDeg);
  double cp = std::cos(pitch_deg * kDeg), sp = std::sin(pitch_deg * kDeg);
  return vf(unit(
      axpy(sp, up, axpy(cp * sy, right, V{cp * cy * front[0], cp * cy * front[1], cp * cy * front[2]}))));
}

std::string coverage_advice(const ViewRange& r) {
  double left = -r.yaw_min, right = r.yaw_max;  // how far round each side the capture went
  if (left >= kEarToEarYawDeg && right >= kEarToEarYawDeg) return "";
  return fmt::format(
      "the capture turned only {:.0f} deg to one side and {:.0f} deg to the other (yaw {:+.0f}..{:+.0f} "
      "deg); the temples and ears, where glasses rest, need at least {:.0f} deg on each side. Film from ear "
      "to ear: turn the head (or walk the phone round it) slowly until each ear faces the camera, keeping "
      "the whole head in the frame",
      std::min(left, right), std::max(left, right), r.yaw_min, r.yaw_max, kEarToEarYawDeg);
}

}  // namespace lorgnette::nerf
