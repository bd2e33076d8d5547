// The ear search's ray field (see ear_rays.h).
#include "fit/ear_rays.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace lorgnette::fit {

EarSideFrame::EarSideFrame(const EarRootInputs& in)
    : temple(in.temple),
      out(in.side * in.d_eye.normalized()),
      up(in.d_up.normalized()),
      fwd(in.d_fwd.normalized()),
      mm_per_unit(in.mm_per_unit) {
  eye_height_mm = (in.eye_corner - in.temple).dot(up) * mm_per_unit;
}

Eigen::Vector3d EarSideFrame::point(double lateral_mm, double depth_mm, double height_mm) const {
  return temple + (lateral_mm * out + depth_mm * fwd + (eye_height_mm + height_mm) * up) / mm_per_unit;
}

void check_ear_search(const EarRootInputs& in, const EarRayOptions& o) {
  if (!(in.mm_per_unit > 0.0)) throw std::invalid_argument("find_ear_root: mm_per_unit must be positive");
  if (in.side != 1 && in.side != -1) throw std::invalid_argument("find_ear_root: side must be +1 or -1");
  for (double s : {o.depth_step_mm, o.lateral_step_mm, o.ray_step_mm})
    if (!(s > 0.0)) throw std::invalid_argument("find_ear_root: steps must be positive");
  if (!(o.back_mm + o.front_mm > 0.0 && o.inward_mm + o.outward_mm > 0.0 && o.above_mm + o.below_mm > 0.0))
    throw std::invalid_argument("find_ear_root: the search window is empty");
  if (!(o.opacity > 0.0 && o.opacity < 1.0))
    throw std::invalid_argument("find_ear_root: opacity must lie in (0, 1)");
}

std::vector<double> ear_grid(double from, double to, double step) {
  std::vector<double> v;
  for (int i = 0; from + i * step <= to + 1e-9; ++i) v.push_back(from + i * step);
  return v;
}

namespace {

// Where a ray's opacity from above reaches the level: its samples' densities from the top down at
// `heights` (ascending, so sample k lies at heights[n - 1 - k]); NaN when it never does.
double ray_stop(const float* density, const std::vector<double>& heights, double target, double dt,
                double step_mm) {
  const size_t n = heights.size();
  double tau = 0.0;
  for (size_t k = 1; k < n; ++k) {
    const double add = 0.5 * (double(density[k - 1]) + double(density[k])) * dt;
    if (tau + add >= target) {
      const double frac = (target - tau) / add;  // within the step from sample k-1 (above) to k
      return heights[n - k] - frac * step_mm;
    }
    tau += add;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

EarRayField cast_ear_rays(const DensityFn& density_of, const EarRootInputs& in, const EarRayOptions& o,
                          const std::vector<double>& depths_mm) {
  const EarSideFrame frame(in);
  EarRayField field;
  field.depths = depths_mm;
  field.laterals = ear_grid(-o.inward_mm, o.outward_mm, o.lateral_step_mm);
  const std::vector<double> heights = ear_grid(-o.below_mm, o.above_mm, o.ray_step_mm);  // from the eyes
  const size_t per_ray = heights.size();
  std::vector<Eigen::Vector3f> pts;
  pts.reserve(depths_mm.size() * field.laterals.size() * per_ray);
  for (double f : depths_mm)
    for (double x : field.laterals)
      for (size_t k = per_ray; k-- > 0;)  // from the top down
        pts.push_back(frame.point(x, f, heights[k]).cast<float>());
  const std::vector<float> density = density_of(pts);
  if (density.size() != pts.size())
    throw std::runtime_error("find_ear_root: the density returned the wrong number of values");

  const double target = -std::log(1.0 - o.opacity), dt = o.ray_step_mm / in.mm_per_unit;
  field.heights.assign(depths_mm.size(), std::vector<double>(field.laterals.size()));
  size_t at = 0;
  for (auto& row : field.heights)
    for (double& h : row) {
      h = ray_stop(&density[at], heights, target, dt, o.ray_step_mm);
      at += per_ray;
    }
  return field;
}

}  // namespace lorgnette::fit
