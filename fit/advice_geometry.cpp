// The advice's measurements on the fitted head and the placed frame (see advice_geometry.h).
#include "fit/advice_geometry.h"

#include <fmt/format.h>

#include <cmath>

namespace lorgnette::fit {

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

AdviceInputs advice_inputs(const GlassesInput& g, const Placement& p, const AdviceHead& h,
                           const DensityFn& density, float thr, const NoseProbeOptions& o) {
  AdviceInputs in;
  const FrameSizes& f = g.sizes;
  const double mpu = h.mm_per_unit;
  in.approximate = h.approximate;
  in.frame_width_mm = f.total_width_mm;
  in.temple_width_mm = (h.temple_l - h.temple_r).norm() * mpu;
  in.bridge_mm = f.bridge_mm;
  in.lens_height_mm = f.lens_height_mm;
  in.temple_length_mm = f.temple_length_mm;
  auto canon = [&](const Eigen::Vector3d& q) { return canonical_at_true_size(p, g.ref.g_c, mpu, q); };
  in.pupil_above_centre_mm = 0.5 * (canon(h.eye_l).y() + canon(h.eye_r).y()) - f.lens_centre_y_mm;
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
