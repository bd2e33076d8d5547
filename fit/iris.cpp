// The limbus in an eye image and the scale it gives (see iris.h).
#include "fit/iris.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "fit/camera_math.h"

namespace lorgnette::fit {

namespace {

double luminance_at(const Image& im, int x, int y) {
  return 0.2126 * im.at(x, y, 0) + 0.7152 * im.at(x, y, 1) + 0.0722 * im.at(x, y, 2);
}

// Row `y` between columns x0..x1 (inclusive), smoothed by [1 2 1] / 4 along the row.
std::vector<double> row_profile(const Image& im, int y, int x0, int x1) {
  std::vector<double> p;
  for (int x = x0; x <= x1; ++x)
    p.push_back(0.25 * luminance_at(im, std::max(0, x - 1), y) + 0.5 * luminance_at(im, x, y) +
                0.25 * luminance_at(im, std::min(im.width - 1, x + 1), y));
  return p;
}

// Offset in (-0.5, 0.5) of the extremum of the parabola through (a, b, c) at (-1, 0, 1).
double parabola_peak(double a, double b, double c) {
  const double den = a - 2.0 * b + c;
  return std::abs(den) < 1e-12 ? 0.0 : std::clamp(0.5 * (a - c) / den, -0.5, 0.5);
}

struct RowEdges {
  bool ok = false;
  double left = 0, right = 0, step = 0;  // profile indices (sub-pixel) and the weaker relative step
};

// The darkest stretch near the guess and the strongest dark-to-light steps either side of it.
RowEdges row_edges(const std::vector<double>& p, double centre, double r0, const IrisEdgeOptions& o) {
  const int n = int(p.size()), half = std::max(1, int(0.5 * r0));
  auto mean_around = [&](int x) {
    double s = 0;
    for (int k = x - half; k <= x + half; ++k) s += p[std::clamp(k, 0, n - 1)];
    return s / (2 * half + 1);
  };
  int xm = -1;
  double darkest = 1e30;
  for (int x = std::max(0, int(centre - r0)); x <= std::min(n - 1, int(centre + r0)); ++x)
    if (double m = mean_around(x); m < darkest) darkest = m, xm = x;
  if (xm < 0) return {};
  auto d = [&](int x) { return 0.5 * (p[std::min(n - 1, x + 1)] - p[std::max(0, x - 1)]); };
  auto strongest = [&](int from, int to, double sign) {
    int best = -1;
    double val = 0;
    for (int x = std::max(1, from); x <= std::min(n - 2, to); ++x)
      if (sign * d(x) > val) val = sign * d(x), best = x;
    return best;
  };
  // From the darkest point outwards: rows near the iris' top and bottom cut it in short chords.
  const int l = strongest(int(xm - 2 * r0), xm - 2, -1.0);
  const int r = strongest(xm + 2, int(xm + 2 * r0), +1.0);
  if (l < 2 || r < 0 || r > n - 3) return {};
  const int reach = std::max(2, int(0.25 * r0));
  const double out_l = p[std::max(0, l - reach)], out_r = p[std::min(n - 1, r + reach)];
  RowEdges e;
  e.step = std::min(out_l > 0 ? (out_l - darkest) / out_l : 0.0, out_r > 0 ? (out_r - darkest) / out_r : 0.0);
  e.left = l + parabola_peak(d(l - 1), d(l), d(l + 1));
  e.right = r + parabola_peak(d(r - 1), d(r), d(r + 1));
  e.ok = e.step >= o.min_relative_step;
  return e;
}

// One row's edges: its height (pixel centre) and the left and right limbus (continuous x).
struct RowChord {
  double y, left, right;
  double centre() const { return 0.5 * (left + right); }
  double half() const { return 0.5 * (right - left); }
};

// The circle through the rows' chords: half^2 + (y - yc)^2 = R^2 is linear in (2 yc, R^2 - yc^2)
// given half^2 + y^2, solved by least squares. False when degenerate.
bool fit_chords(const std::vector<RowChord>& rows, double* yc, double* radius) {
  if (rows.size() < 3) return false;
  Eigen::MatrixXd a(rows.size(), 2);
  Eigen::VectorXd b(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    a.row(i) << rows[i].y, 1.0;
    b(i) = rows[i].half() * rows[i].half() + rows[i].y * rows[i].y;
  }
  const Eigen::Vector2d s = a.colPivHouseholderQr().solve(b);
  *yc = 0.5 * s(0);
  const double r2 = s(1) + *yc * *yc;
  if (!(r2 > 0.0) || !std::isfinite(r2)) return false;
  *radius = std::sqrt(r2);
  return true;
}

// How far a row's half chord is from the circle (yc, radius).
double chord_off(const RowChord& r, double yc, double radius) {
  const double dy = r.y - yc;
  return std::abs(r.half() - std::sqrt(std::max(0.0, radius * radius - dy * dy)));
}

// Rows off the iris (an eyelid's lash line, a lid crease) break the pattern: their chords' centres
// stray from the others', or their chords do not lie on the circle. The first go by the median
// centre; for the second, every pair of rows proposes a circle (radius within 2x of `r0`), the one
// most rows agree with (within `max_residual_px`) wins and is refitted on those rows (RANSAC made
// exhaustive: a few dozen rows, so every pair is cheap and the result deterministic).
bool robust_circle(std::vector<RowChord> rows, double r0, const IrisEdgeOptions& o, Eigen::Vector2d* centre,
                   double* radius, int* used) {
  if (rows.empty()) return false;
  std::vector<double> cs;
  for (const auto& r : rows) cs.push_back(r.centre());
  std::nth_element(cs.begin(), cs.begin() + cs.size() / 2, cs.end());
  const double cx = cs[cs.size() / 2];
  rows.erase(
      std::remove_if(rows.begin(), rows.end(),
                     [&](const RowChord& r) { return std::abs(r.centre() - cx) > 2.0 * o.max_residual_px; }),
      rows.end());
  std::vector<RowChord> best;
  for (size_t i = 0; i < rows.size(); ++i)
    for (size_t j = i + 1; j < rows.size(); ++j) {
      double yc = 0, rad = 0;
      if (!fit_chords({rows[i], rows[j], rows[i]}, &yc, &rad) || rad < 0.5 * r0 || rad > 2.0 * r0) continue;
      std::vector<RowChord> agree;
      for (const auto& r : rows)
        if (chord_off(r, yc, rad) <= o.max_residual_px) agree.push_back(r);
      if (agree.size() > best.size()) best.swap(agree);
    }
  double yc = 0;
  if (int(best.size()) < o.min_rows || !fit_chords(best, &yc, radius)) return false;
  double sum = 0;
  for (const auto& r : best) sum += r.centre();
  *centre = Eigen::Vector2d(sum / best.size(), yc);
  *used = int(best.size());
  return true;
}

}  // namespace

IrisEdges find_iris_edges(const Image& im, const Eigen::Vector2d& c, double r0, const IrisEdgeOptions& o) {
  IrisEdges e;
  if (im.empty() || im.channels < 3) return e.why = "no colour image of the eye", e;
  if (!(r0 >= 3.0)) return e.why = fmt::format("the iris would be {:.1f} px across: too small", 2 * r0), e;
  const int x0 = std::max(0, int(std::floor(c.x() - o.search_radii * r0)));
  const int x1 = std::min(im.width - 1, int(std::ceil(c.x() + o.search_radii * r0)));
  const int y0 = std::max(0, int(std::floor(c.y() - o.row_radii * r0)));
  const int y1 = std::min(im.height - 1, int(std::ceil(c.y() + o.row_radii * r0)));
  std::vector<RowChord> rows;
  std::vector<double> steps;
  for (int y = y0; y <= y1; ++y) {
    const RowEdges r = row_edges(row_profile(im, y, x0, x1), c.x() - x0, r0, o);
    if (!r.ok) continue;
    rows.push_back(
        {y + 0.5, x0 + r.left + 0.5, x0 + r.right + 0.5});  // index i: the pixel centred at x0 + i + 0.5
    steps.push_back(r.step);
  }
  if (int(steps.size()) < o.min_rows)
    return e.why = fmt::format("weak edges: a clear limbus in {} rows (need {})", steps.size(), o.min_rows),
           e;
  double radius = 0;
  if (!robust_circle(rows, r0, o, &e.centre_px, &radius, &e.rows))
    return e.why = "the edges found do not lie on a circle", e;
  if (radius < 0.5 * r0 || radius > 2.0 * r0)
    return e.why =
               fmt::format("an iris {:.1f} px across where about {:.1f} was expected", 2 * radius, 2 * r0),
           e;
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  e.relative_step = steps[steps.size() / 2];
  e.diameter_px = 2.0 * radius;
  e.found = true;
  return e;
}

double pixels_to_units(const Camera& cam, const Eigen::Vector3d& point, double px) {
  const double depth = (point - camera_center(cam)).dot(camera_forward(cam));
  if (!(depth > 0.0)) throw std::runtime_error("pixels_to_units: the point is behind the camera");
  return px * depth / cam.fx;
}

IrisScale iris_scale(const std::vector<IrisMeasurement>& ms, double mean_face_mpu,
                     const IrisScaleOptions& o) {
  IrisScale s;
  std::vector<double> left, right, all;
  int closed = 0, weak = 0;
  std::string weak_why, closed_why;
  for (const IrisMeasurement& m : ms) {
    if (m.closed) {
      ++closed, closed_why = m.edges.why;
    } else if (!m.edges.found || !(m.diameter_units > 0.0)) {
      ++weak, weak_why = m.edges.why;
    } else {
      (m.eye > 0 ? left : right).push_back(m.diameter_units);
      all.push_back(m.diameter_units);
    }
  }
  if (int(left.size()) < o.min_per_eye || int(right.size()) < o.min_per_eye)
    return s.why = fmt::format(
               "irises measured in {} view(s) of the left eye and {} of the right ({} closed{}{}, {} without "
               "a "
               "clear limbus{}{})",
               left.size(), right.size(), closed, closed_why.empty() ? "" : ": ", closed_why, weak,
               weak_why.empty() ? "" : ": ", weak_why),
           s;
  auto mean = [](const std::vector<double>& v) {
    double t = 0;
    for (double x : v) t += x;
    return t / double(v.size());
  };
  const double ml = mean(left), mr = mean(right), d = mean(all);
  if (std::abs(ml - mr) > o.max_eye_disagreement * d)
    return s.why =
               fmt::format("the two irises disagree: left {:.4g}, right {:.4g} units ({:.0f} % > {:.0f} %)",
                           ml, mr, 100 * std::abs(ml - mr) / d, 100 * o.max_eye_disagreement),
           s;
  double var = 0;
  for (double x : all) var += (x - d) * (x - d);
  var /= double(std::max<size_t>(1, all.size() - 1));
  const double rel = std::sqrt(std::pow(kIrisDiameterSdMm / kIrisDiameterMm, 2) + var / (d * d) / all.size());
  s.diameter_units = d;
  s.measurements = int(all.size());
  s.mm_per_unit = kIrisDiameterMm / d;
  s.mm_per_unit_uncertainty = rel * s.mm_per_unit;
  if (mean_face_mpu > 0.0 && std::abs(s.mm_per_unit / mean_face_mpu - 1.0) > o.max_gap_to_mean_face)
    return s.why = fmt::format(
               "the irises give {:.4g} mm per unit, {:.0f} % from the mean face's {:.4g}: "
               "the edges found are probably not the limbus",
               s.mm_per_unit, 100 * std::abs(s.mm_per_unit / mean_face_mpu - 1.0), mean_face_mpu),
           s;
  s.ok = true;
  s.why = fmt::format("{} iris measurements (left {:.4g}, right {:.4g} units): {:.4g} +- {:.2g} mm per unit",
                      all.size(), ml, mr, s.mm_per_unit, s.mm_per_unit_uncertainty);
  return s;
}

}  // namespace lorgnette::fit
