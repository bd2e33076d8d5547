// The placement transform's checks, typed forms and rough stand-in (placement_transform.h).
#include "fit/placement_transform.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "host/util/bounds.h"

namespace lorgnette::fit {

void check_transform(const Transform& m, const std::string& what) {
  if (!m.allFinite()) throw std::invalid_argument(what + ": the matrix has a non-finite entry");
  if (m(3, 0) != 0.0 || m(3, 1) != 0.0 || m(3, 2) != 0.0 || m(3, 3) != 1.0)
    throw std::invalid_argument(
        fmt::format("{}: the last row must be 0 0 0 1 (an affine transform, row-major), found {} {} {} {}",
                    what, m(3, 0), m(3, 1), m(3, 2), m(3, 3)));
  const Eigen::Matrix3d a = m.block<3, 3>(0, 0);
  double product = 1.0;
  for (int k = 0; k < 3; ++k) {
    double s = a.col(k).norm();
    if (!(s >= kMinTransformScale && s <= kMaxTransformScale))
      throw std::invalid_argument(fmt::format(
          "{}: the frame's axis {} is scaled by {:g} scene units per mm, outside {:g}..{:g} (an all-zero or "
          "broken transform): re-run `lorgnette fit` or fix the matrix",
          what, "xyz"[k], s, kMinTransformScale, kMaxTransformScale));
    product *= s;
  }
  if (std::abs(a.determinant()) < 1e-6 * product)
    throw std::invalid_argument(what + ": the transform flattens the frame (its axes are parallel)");
  if (!(m.block<3, 1>(0, 3).cwiseAbs().maxCoeff() <= kMaxTranslation))
    throw std::invalid_argument(
        fmt::format("{}: the translation is beyond {:g} scene units", what, kMaxTranslation));
}

Transform trs_transform(const std::array<float, 3>& t, const std::array<float, 3>& r_deg, float s) {
  for (int i = 0; i < 3; ++i)
    check_bound(bounds::kTranslate, t[i]), check_bound(bounds::kRotateDeg, r_deg[i]);
  check_bound(bounds::kGlassesScale, s);
  const double k = M_PI / 180.0;
  Eigen::Matrix3d rot = (Eigen::AngleAxisd(r_deg[2] * k, Eigen::Vector3d::UnitZ()) *
                         Eigen::AngleAxisd(r_deg[1] * k, Eigen::Vector3d::UnitY()) *
                         Eigen::AngleAxisd(r_deg[0] * k, Eigen::Vector3d::UnitX()))
                            .toRotationMatrix();
  Transform m = Transform::Identity();
  m.block<3, 3>(0, 0) = rot * double(s);
  m.block<3, 1>(0, 3) = Eigen::Vector3d(t[0], t[1], t[2]);
  check_transform(m, "--translate/--rotate/--scale");
  return m;
}

Transform parse_transform(const std::string& text, const std::string& what) {
  std::istringstream in(std::regex_replace(text, std::regex("[,\\[\\]]"), " "));
  std::vector<double> v;
  for (std::string tok; in >> tok;) {
    try {
      size_t used = 0;
      v.push_back(std::stod(tok, &used));
      if (used != tok.size()) throw std::invalid_argument(tok);
    } catch (const std::exception&) {
      throw std::invalid_argument(what + ": '" + tok + "' is not a number");
    }
  }
  if (v.size() != 16)
    throw std::invalid_argument(
        fmt::format("{}: expected 16 numbers (row-major 4x4), got {}", what, v.size()));
  Transform m;
  for (int i = 0; i < 16; ++i) m(i / 4, i % 4) = v[i];
  check_transform(m, what);
  return m;
}

Transform rough_placement(double frame_width_mm, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                          const HeadAxes& axes) {
  const Eigen::Vector3d dir[3] = {axes.x, axes.up, axes.front};
  double mn[3] = {1e300, 1e300, 1e300}, mx[3] = {-1e300, -1e300, -1e300};
  for (int corner = 0; corner < 8; ++corner) {
    Eigen::Vector3d p(corner & 1 ? hi[0] : lo[0], corner & 2 ? hi[1] : lo[1], corner & 4 ? hi[2] : lo[2]);
    for (int a = 0; a < 3; ++a) {
      double d = (p - axes.center).dot(dir[a]);
      mn[a] = std::min(mn[a], d), mx[a] = std::max(mx[a], d);
    }
  }
  const double s = 0.8 * (mx[0] - mn[0]) / std::max(frame_width_mm, 1.0);
  Eigen::Vector3d pos = axes.center + dir[0] * (0.5 * (mn[0] + mx[0])) +
                        dir[1] * (mn[1] + 0.6 * (mx[1] - mn[1])) + dir[2] * (mx[2] - 0.12 * (mx[2] - mn[2]));
  Transform m = Transform::Identity();
  for (int a = 0; a < 3; ++a) m.block<3, 1>(0, a) = s * dir[a];
  m.block<3, 1>(0, 3) = pos;
  return m;
}

}  // namespace lorgnette::fit
