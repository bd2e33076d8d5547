// Pupillary distance from the limbus centres (see pupil_distance.h).
#include "fit/pupil_distance.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace lorgnette::fit {
namespace {

struct EyeCentre {
  int n = 0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  double iris_units = 0.0;  // mean diameter
};

EyeCentre eye_centre(const std::vector<IrisMeasurement>& ms, int eye) {
  EyeCentre e;
  for (const IrisMeasurement& m : ms)
    if (m.eye == eye && m.edges.found) e.mean += m.centre, e.iris_units += m.diameter_units, ++e.n;
  if (e.n) e.mean /= e.n, e.iris_units /= e.n;
  return e;
}

// The standard error of the eye's centres along `axis`, floored (PupilDistanceOptions).
double centre_sigma(const std::vector<IrisMeasurement>& ms, const EyeCentre& e, int eye,
                    const Eigen::Vector3d& axis, double floor_share) {
  double ss = 0.0;
  for (const IrisMeasurement& m : ms)
    if (m.eye == eye && m.edges.found) ss += std::pow((m.centre - e.mean).dot(axis), 2);
  const double se = e.n > 1 ? std::sqrt(ss / (e.n - 1) / e.n) : 0.0;
  return std::max(se, floor_share * e.iris_units);
}

// Why `eye` (+1 left, -1 right) has no limbus: closed in every view that measured it (the lids hide
// the limbus: the views' own reason), or none found.
std::string why_no_limbus(const std::vector<IrisMeasurement>& ms, int eye) {
  const char* name = eye > 0 ? "left" : "right";
  int views = 0, closed = 0;
  std::string closed_why;
  for (const IrisMeasurement& m : ms)
    if (m.eye == eye) ++views, closed += m.closed, closed_why = m.closed ? m.edges.why : closed_why;
  if (views > 0 && closed == views) return fmt::format("the {} eye is closed ({})", name, closed_why);
  return fmt::format("no limbus found in the {} eye's views", name);
}

}  // namespace

PupilDistance pupil_distance(const std::vector<IrisMeasurement>& ms, const PupilDistanceOptions& o) {
  PupilDistance p;
  const EyeCentre l = eye_centre(ms, +1), r = eye_centre(ms, -1);
  if (!l.n || !r.n) {
    p.why = why_no_limbus(ms, !l.n ? +1 : -1);
    return p;
  }
  p.left = l.mean, p.right = r.mean;
  p.units = (l.mean - r.mean).norm();
  if (!(p.units > 0.0)) return p.why = "the two limbus centres coincide", p;
  const Eigen::Vector3d axis = (l.mean - r.mean) / p.units;
  p.sigma_left = centre_sigma(ms, l, +1, axis, o.sigma_floor_per_iris);
  p.sigma_right = centre_sigma(ms, r, -1, axis, o.sigma_floor_per_iris);
  p.ok = true;
  return p;
}

}  // namespace lorgnette::fit
