// Telling hair from skin by colour for the temple test (see hair.h).
#include "fit/hair.h"

#include <Eigen/Geometry>
#include <algorithm>

namespace lorgnette::fit {

double luminance(const Eigen::Vector3f& c) { return 0.2126 * c.x() + 0.7152 * c.y() + 0.0722 * c.z(); }

std::optional<SkinTone> skin_tone(const ColourFn& colour, const std::vector<Eigen::Vector3d>& skin_points,
                                  const Eigen::Vector3d& view_dir) {
  if (!colour || skin_points.empty()) return std::nullopt;
  std::vector<Eigen::Vector3f> p, d;
  for (const auto& q : skin_points)
    p.push_back(q.cast<float>()), d.push_back(view_dir.normalized().cast<float>());
  std::vector<Eigen::Vector3f> c = colour(p, d);
  if (c.size() != p.size()) return std::nullopt;
  std::sort(c.begin(), c.end(), [](const auto& a, const auto& b) { return luminance(a) < luminance(b); });
  SkinTone t;
  t.rgb = c[(c.size() - 1) / 2];  // the lower median: a bright outlier (specular) cannot raise it
  t.luminance = luminance(t.rgb);
  t.samples = int(c.size());
  if (!(t.luminance > 0.0)) return std::nullopt;
  return t;
}

std::optional<double> ear_top_luminance(const ColourFn& colour,
                                        const std::vector<std::vector<Eigen::Vector3d>>& top_per_depth,
                                        const Eigen::Vector3d& up) {
  if (!colour) return std::nullopt;
  std::vector<Eigen::Vector3f> points, dirs;
  for (const auto& depth : top_per_depth)
    for (const auto& q : depth)
      points.push_back(q.cast<float>()), dirs.push_back(-up.normalized().cast<float>());
  if (points.empty()) return std::nullopt;
  const std::vector<Eigen::Vector3f> rgb = colour(points, dirs);
  if (rgb.size() != points.size()) return std::nullopt;
  std::vector<double> brightest;
  size_t i = 0;
  for (const auto& depth : top_per_depth) {
    if (depth.empty()) continue;
    double b = 0.0;
    for (size_t k = 0; k < depth.size(); ++k, ++i) b = std::max(b, luminance(rgb[i]));
    brightest.push_back(b);
  }
  std::nth_element(brightest.begin(), brightest.begin() + brightest.size() / 2, brightest.end());
  return brightest[brightest.size() / 2];
}

DensityFn density_without_hair(const HeadProbe& head, ColourFn colour, const SkinTone& skin,
                               const HairOptions& options) {
  const float solid = head.contact.density_threshold;
  const double darkest_skin = options.max_luminance_ratio * skin.luminance;
  return [density = head.density, colour = std::move(colour), axis = head.axis_point, up = head.d_up, solid,
          darkest_skin](const std::vector<Eigen::Vector3f>& points) {
    std::vector<float> sigma = density(points);
    std::vector<Eigen::Vector3f> dense, dirs;
    std::vector<size_t> who;
    for (size_t i = 0; i < points.size(); ++i) {
      if (!(sigma[i] > solid)) continue;
      Eigen::Vector3d r = points[i].cast<double>() - axis;
      r -= r.dot(up) * up;  // horizontal, from the axis out through the point
      dense.push_back(points[i]);
      dirs.push_back(
          (r.norm() > 1e-12 ? -r.normalized() : Eigen::Vector3d(-up.unitOrthogonal())).cast<float>());
      who.push_back(i);
    }
    if (dense.empty()) return sigma;
    std::vector<Eigen::Vector3f> c = colour(dense, dirs);
    if (c.size() != dense.size()) return sigma;  // no colour: everything dense stays solid
    for (size_t k = 0; k < dense.size(); ++k)
      if (luminance(c[k]) < darkest_skin) sigma[who[k]] = 0.0f;
    return sigma;
  };
}

}  // namespace lorgnette::fit
