// Sphere-cap camera rigs; see camera_rig.h. The (yaw, pitch) samples come from the R2 sequence
// (Roberts' generalised golden ratio) with a seeded offset: evenly spread for every prefix.
#include "synth/camera_rig.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace lorgnette::synth {

Camera look_at_camera(const Eigen::Vector3f& eye, const Eigen::Vector3f& target, int width, int height,
                      float fov_y) {
  Eigen::Vector3f back = (eye - target).normalized();
  // World +y is up, unless the camera looks straight up or down: then the image's up is -z or +z.
  Eigen::Vector3f up = Eigen::Vector3f::UnitY();
  if (up.cross(back).norm() < 1e-6f) up = back.y() > 0 ? Eigen::Vector3f(0, 0, -1) : Eigen::Vector3f(0, 0, 1);
  auto v = [](const Eigen::Vector3f& p) { return lgn_vec3(p.x(), p.y(), p.z()); };
  return camera_look_at(v(eye), v(target), v(up), fov_y * 180.0f / float(M_PI), static_cast<lgn_uint>(width),
                        static_cast<lgn_uint>(height));
}

Eigen::Vector3f rig_position(const RigOptions& rig, float yaw_deg, float pitch_deg) {
  float yaw = yaw_deg * float(M_PI) / 180.0f, pitch = pitch_deg * float(M_PI) / 180.0f;
  Eigen::Vector3f dir(std::sin(yaw) * std::cos(pitch), std::sin(pitch), std::cos(yaw) * std::cos(pitch));
  return rig.target + rig.distance * dir;
}

Camera rig_camera(const RigOptions& rig, float yaw_deg, float pitch_deg) {
  float fov = rig.fov_y_deg > 0.0f ? rig.fov_y_deg * float(M_PI) / 180.0f
                                   : 2.0f * std::atan(rig.frame_radius / rig.distance) * 1.05f;
  if (rig.fov_y_deg <= 0.0f && rig.width < rig.height)
    fov = 2.0f * std::atan(std::tan(0.5f * fov) * rig.height / rig.width);
  return look_at_camera(rig_position(rig, yaw_deg, pitch_deg), rig.target, rig.width, rig.height, fov);
}

std::vector<RigView> make_camera_rig(const RigOptions& rig) {
  if (rig.views < 1 || rig.views > 100000)
    throw std::runtime_error(fmt::format("camera rig: {} views requested; use 1..100000", rig.views));
  if (rig.width < 16 || rig.height < 16 || rig.width > 8192 || rig.height > 8192)
    throw std::runtime_error(
        fmt::format("camera rig: image size {}x{} is out of range (16..8192)", rig.width, rig.height));
  if (!(rig.yaw_min_deg <= rig.yaw_max_deg) || rig.yaw_min_deg < -180 || rig.yaw_max_deg > 180)
    throw std::runtime_error(
        fmt::format("camera rig: yaw range [{}, {}] must be ordered and within [-180, 180] degrees",
                    rig.yaw_min_deg, rig.yaw_max_deg));
  if (!(rig.pitch_min_deg <= rig.pitch_max_deg) || rig.pitch_min_deg < -80 || rig.pitch_max_deg > 80)
    throw std::runtime_error(
        fmt::format("camera rig: pitch range [{}, {}] must be ordered and within [-80, 80] degrees",
                    rig.pitch_min_deg, rig.pitch_max_deg));
  if (!(rig.distance > 0) || !(rig.frame_radius > 0) || rig.frame_radius >= rig.distance)
    throw std::runtime_error("camera rig: the distance must be positive and larger than the framed radius");
  std::mt19937_64 rng(rig.seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double g = 1.32471795724474602596, a1 = 1.0 / g, a2 = 1.0 / (g * g);
  double o1 = rig.seed == 0 ? 0.5 : uni(rng), o2 = rig.seed == 0 ? 0.5 : uni(rng);
  std::vector<RigView> views;
  if (rig.handheld) {
    // One sweep: yaw in order (a video), pitch a slow wave plus jitter inside its range.
    const float span = rig.yaw_max_deg - rig.yaw_min_deg,
                step = rig.views > 1 ? span / float(rig.views - 1) : 0.0f;
    const float phase = float(2.0 * M_PI * uni(rng)), mid = 0.5f * (rig.pitch_min_deg + rig.pitch_max_deg);
    const float half = 0.5f * (rig.pitch_max_deg - rig.pitch_min_deg);
    for (int i = 0; i < rig.views; ++i) {
      float yaw = std::clamp(rig.yaw_min_deg + step * (float(i) + 0.3f * float(uni(rng) - 0.5)),
                             rig.yaw_min_deg, rig.yaw_max_deg);
      float wave = std::sin(phase + 3.0f * float(M_PI) * float(i) / float(std::max(1, rig.views - 1)));
      float pitch = std::clamp(mid + half * (0.7f * wave + 0.6f * float(uni(rng) - 0.5)), rig.pitch_min_deg,
                               rig.pitch_max_deg);
      RigOptions r = rig;
      r.distance = rig.distance * (1.0f + rig.distance_jitter * float(2.0 * uni(rng) - 1.0));
      for (int a = 0; a < 3; ++a)
        r.target[a] += rig.aim_jitter * rig.frame_radius * float(2.0 * uni(rng) - 1.0);
      views.push_back({rig_camera(r, yaw, pitch), yaw, pitch});
    }
    return views;
  }
  for (int i = 0; i < rig.views; ++i) {
    double s = std::fmod(o1 + a1 * i, 1.0), t = std::fmod(o2 + a2 * i, 1.0);
    float yaw = rig.yaw_min_deg + float(s) * (rig.yaw_max_deg - rig.yaw_min_deg);
    float pitch = rig.pitch_min_deg + float(t) * (rig.pitch_max_deg - rig.pitch_min_deg);
    views.push_back({rig_camera(rig, yaw, pitch), yaw, pitch});
  }
  return views;
}

}  // namespace lorgnette::synth
