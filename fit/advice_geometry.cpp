// The advice's measurements on the fitted head and the placed frame (see advice_geometry.h).
#include "fit/advice_geometry.h"

#include <fmt/format.h>

#include <cmath>

namespace lorgnette::fit {

Placement advice_placement(const GlassesRefPoints& g, const PlaceInputs& points, ScalePolicy used,
                           const Placement& drawn, const HeadProbe* head, const Eigen::Vector3d& d_fwd) {
  if (used == ScalePolicy::kTrueSize) return drawn;
  Placement p = place_glasses(g, points, ScalePolicy::kTrueSize);
  if (head && !head->frame_points.empty()) refine_contact(p, *head, d_fwd);
  return p;
}

Eigen::Vector3d canonical_at_true_size(const Placement& p, const Eigen::Vector3d& g_c, double mpu,
                                       const Eigen::Vector3d& q) {
  const Eigen::Vector3d bridge = p.transform.block<3, 3>(0, 0) * g_c + p.transform.block<3, 1>(0, 3);
  return g_c + p.rotation.transpose() * (q - bridge) * mpu;
}

namespace {

// Scene points of canonical mm points for the frame at true size (the inverse of the above).
std::vector<Eigen::Vector3f> to_scene(const Placement& p, const Eigen::Vector3d& g_c, double mpu,
                                      const std::vector<Eigen::Vector3d>& canon) {
  const Eigen::Vector3d bridge = p.transform.block<3, 3>(0, 0) * g_c + p.transform.block<3, 1>(0, 3);
  std::vector<Eigen::Vector3f> out;
  for (const auto& g : canon) out.push_back((bridge + p.rotation * (g - g_c) / mpu).cast<float>());
  return out;
}

std::vector<bool> solid(const DensityFn& density, float thr, const std::vector<Eigen::Vector3f>& pts) {
  const std::vector<float> s = density(pts);
  std::vector<bool> out(pts.size(), false);
  for (size_t i = 0; i < pts.size() && i < s.size(); ++i) out[i] = s[i] > thr;
  return out;
}

}  // namespace

double nose_width_mm(const DensityFn& density, float thr, const Placement& p, const Eigen::Vector3d& g_c,
                     double mpu, double y, const NoseProbeOptions& o, std::string* why) {
  // The nose's front on the mid line at this height: the first solid point coming from the front.
  std::vector<Eigen::Vector3d> line;
  for (double z = g_c.z() + o.search_mm; z >= g_c.z() - o.search_mm; z -= o.step_mm)
    line.emplace_back(g_c.x(), y, z);
  const std::vector<bool> on_line = solid(density, thr, to_scene(p, g_c, mpu, line));
  size_t front = 0;
  while (front < line.size() && !on_line[front]) ++front;
  if (front == line.size()) return *why = "no nose on the frame's mid line at the lens' centre height", 0.0;
  const double z = line[front].z() - o.pad_depth_mm;
  // Outwards both ways from the mid line at the pads' depth, to the first point outside.
  std::vector<Eigen::Vector3d> across;
  const int n = int(std::ceil(0.5 * o.max_width_mm / o.step_mm)) + 1;
  for (int side : {-1, +1})
    for (int k = 0; k <= n; ++k) across.emplace_back(g_c.x() + side * k * o.step_mm, y, z);
  const std::vector<bool> in = solid(density, thr, to_scene(p, g_c, mpu, across));
  if (!in[0]) return *why = fmt::format("the nose is hollow {:.0f} mm behind its front", o.pad_depth_mm), 0.0;
  double width = 0.0;
  for (int s = 0; s < 2; ++s) {
    int k = 1;
    while (k <= n && in[s * (n + 1) + k]) ++k;
    if (k > n)
      return *why =
                 fmt::format("the slice there is wider than {:.0f} mm (cheeks, not a nose)", o.max_width_mm),
             0.0;
    width += (k - 0.5) * o.step_mm;  // the edge lies between the last point inside and the first outside
  }
  return width;
}

double temple_width_mm(const DensityFn& density, float thr, const Placement& p, const Eigen::Vector3d& g_c,
                       const AdviceHead& h, const TempleProbeOptions& o, std::string* why) {
  const double mpu = h.mm_per_unit;
  auto canon = [&](const Eigen::Vector3d& q) { return canonical_at_true_size(p, g_c, mpu, q); };
  Eigen::Vector3d side_point[2];
  const Eigen::Vector3d corners[2] = {canon(h.corner_r), canon(h.corner_l)};
  const Eigen::Vector3d ears[2] = {canon(h.ear_r), canon(h.ear_l)};
  for (int s = 0; s < 2; ++s) {
    const double sign = s == 0 ? -1.0 : 1.0;  // canonical x: the wearer's left is +
    const Eigen::Vector3d& c = corners[s];
    const double y = c.y(), z = c.z() - o.depth_share * (c.z() - ears[s].z());
    // Inwards from outside the head to the first solid point: the side of the head there. The probe
    // ends a little inside the eye corner: a head is wider at its temples than between its outer eye
    // corners, so anything found further in (the nose, a hole's far wall) is not a temple.
    std::vector<Eigen::Vector3d> line;
    for (double x = std::abs(c.x()) + o.reach_mm; x >= std::abs(c.x()) - o.inside_corner_mm; x -= o.step_mm)
      line.emplace_back(sign * x, y, z);
    const std::vector<bool> in = solid(density, thr, to_scene(p, g_c, mpu, line));
    size_t k = 0;
    while (k < line.size() && !in[k]) ++k;
    if (k == 0) return *why = "the probe beside the temple starts inside the head", 0.0;
    if (k == line.size()) return *why = "no side of the head at the temples", 0.0;
    side_point[s] = line[k];
    side_point[s].x() += sign * 0.5 * o.step_mm;  // the edge lies between the last point out and the first in
  }
  return (side_point[1] - side_point[0]).norm();
}

AdviceInputs advice_inputs(const GlassesInput& g, const Placement& p, const AdviceHead& h,
                           const DensityFn& density, float thr, const NoseProbeOptions& o) {
  AdviceInputs in;
  const FrameSizes& f = g.sizes;
  const double mpu = h.mm_per_unit;
  in.approximate = h.approximate;
  in.frame_width_mm = f.total_width_mm;
  if (density)
    in.temple_width_mm = temple_width_mm(density, thr, p, g.ref.g_c, h, {}, &in.why_no_temples);
  else
    in.why_no_temples = "no density to measure the head's width on";
  in.bridge_mm = f.bridge_mm;
  in.lens_height_mm = f.lens_height_mm;
  in.temple_length_mm = f.temple_length_mm;
  auto canon = [&](const Eigen::Vector3d& q) { return canonical_at_true_size(p, g.ref.g_c, mpu, q); };
  const Eigen::Vector3d& pupil_l = h.limbus ? h.pupil_l : h.eye_l;
  const Eigen::Vector3d& pupil_r = h.limbus ? h.pupil_r : h.eye_r;
  in.pupil_above_centre_mm = 0.5 * (canon(pupil_l).y() + canon(pupil_r).y()) - f.lens_centre_y_mm;
  if (!h.limbus) in.why_pupils_from_landmarks = h.why_no_limbus.empty() ? "no limbus found" : h.why_no_limbus;
  if (g.ref.has_hinges)
    in.hinge_to_ear_mm =
        0.5 * ((g.ref.hinge_l - canon(h.ear_l)).norm() + (g.ref.hinge_r - canon(h.ear_r)).norm());
  else
    in.why_no_hinges = "the frame's hinges were not found";
  if (f.bridge_mm > 0 && density)
    in.nose_width_mm = nose_width_mm(density, thr, p, g.ref.g_c, mpu, f.lens_centre_y_mm, o, &in.why_no_nose);
  else if (!density)
    in.why_no_nose = "no density to measure the nose on";
  return in;
}

}  // namespace lorgnette::fit
