// Surface depths along rays through a ViewSource's density (see ray_surface.h).
#include "fit/ray_surface.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace lorgnette::fit {
namespace {

// Coarse pass over the whole range, then a fine pass over the coarse step where the event happened:
// ~1 mm then ~0.02 mm on the scenes the fit sees (orbit distances of 0.5-1 m).
constexpr int kCoarse = 512, kFine = 64;

std::vector<float> densities(ViewSource& source, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                             double a, double b, int count) {
  std::vector<Eigen::Vector3f> pts;
  pts.reserve(count);
  for (int i = 0; i < count; ++i)
    pts.push_back((origin + (a + (b - a) * i / (count - 1)) * dir).cast<float>());
  std::vector<float> d = source.density(pts);
  if (d.size() != pts.size())
    throw std::runtime_error("ViewSource::density returned the wrong number of values");
  return d;
}

}  // namespace

bool first_surface_hit(ViewSource& source, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                       double t0, double t1, float threshold, double* t_hit) {
  auto first_above = [&](double a, double b, int count) {
    std::vector<float> d = densities(source, origin, dir, a, b, count);
    for (int i = 0; i < count; ++i)
      if (d[i] > threshold) return i;
    return -1;
  };
  int i = first_above(t0, t1, kCoarse);
  if (i < 0) return false;
  double step = (t1 - t0) / (kCoarse - 1), hi = t0 + step * i, lo = std::max(t0, hi - step);
  int j = i > 0 ? first_above(lo, hi, kFine) : 0;
  *t_hit = j >= 0 ? lo + (hi - lo) * j / (kFine - 1) : hi;
  return true;
}

bool opacity_depth(ViewSource& source, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t0,
                   double t1, double level, double* t_hit) {
  if (!(level > 0.0 && level < 1.0)) throw std::invalid_argument("opacity_depth: level must lie in (0, 1)");
  const double target = -std::log(1.0 - level);  // optical depth to reach
  // Trapezoid optical depth over [a, b] added to *tau; returns the depth where it reaches the target,
  // interpolated linearly within the sample step, or -1 when it does not. *tau stops at the start of
  // the step that reaches it, and *start is that step's start.
  auto reach = [&](double a, double b, int count, double* tau, double* start) {
    std::vector<float> d = densities(source, origin, dir, a, b, count);
    const double dt = (b - a) / (count - 1);
    for (int i = 1; i < count; ++i) {
      double add = 0.5 * (double(d[i - 1]) + double(d[i])) * dt;
      if (*tau + add >= target) {
        *start = a + dt * (i - 1);
        return a + dt * (i - 1 + (target - *tau) / add);
      }
      *tau += add;
    }
    return -1.0;
  };
  double tau = 0.0, lo = t0, unused = 0.0;
  if (reach(t0, t1, kCoarse, &tau, &lo) < 0.0) return false;
  // Refine over the coarse step that reached it, from the optical depth accumulated before that step
  // (tau stops there). The finer trapezoid can fall short where the coarse one overshot a jump: then
  // the level is reached at the step's end.
  const double step = (t1 - t0) / (kCoarse - 1);
  double fine = reach(lo, std::min(t1, lo + step), kFine, &tau, &unused);
  *t_hit = fine >= 0.0 ? fine : std::min(t1, lo + step);
  return true;
}

}  // namespace lorgnette::fit
