// Haze is not a head (see opaque.h).
#include "fit/opaque.h"

#include <Eigen/Geometry>
#include <cmath>

namespace lorgnette::fit {

DensityFn density_behind_opacity(const HeadProbe& head, DensityFn value) {
  const float solid = head.contact.density_threshold;
  const double step = kOpacityStepMm / head.mm_per_unit;
  const int n = int(std::lround(kOpacityReachMm / kOpacityStepMm));
  const double needed = -std::log(1.0 - kHeadOpacity);  // the optical depth of that opacity
  return [density = head.density, value = std::move(value), axis = head.axis_point, up = head.d_up, solid,
          step, n, needed](const std::vector<Eigen::Vector3f>& points) {
    std::vector<float> sigma = value(points);
    std::vector<Eigen::Vector3f> line;
    std::vector<size_t> who;
    for (size_t i = 0; i < points.size() && i < sigma.size(); ++i) {
      if (!(sigma[i] > solid)) continue;
      Eigen::Vector3d r = points[i].cast<double>() - axis;
      r -= r.dot(up) * up;  // horizontal, from the axis out through the point
      const Eigen::Vector3d out = r.norm() > 1e-12 ? r.normalized() : Eigen::Vector3d(up.unitOrthogonal());
      for (int k = 0; k < n; ++k)
        line.push_back((points[i].cast<double>() + (k + 0.5) * step * out).cast<float>());
      who.push_back(i);
    }
    if (who.empty()) return sigma;
    const std::vector<float> along = density(line);
    if (along.size() != line.size()) return sigma;
    for (size_t j = 0; j < who.size(); ++j) {
      double depth = 0.0;
      for (int k = 0; k < n; ++k) {
        const float s = along[j * size_t(n) + size_t(k)];
        depth += std::isfinite(s) && s > 0.0f ? double(s) * step : 0.0;
      }
      if (depth < needed) sigma[who[j]] = 0.0f;
    }
    return sigma;
  };
}

}  // namespace lorgnette::fit
