// The framed head of a placement (head_framing.h).
#include "fit/head_framing.h"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

namespace lorgnette::fit {

render::FramedSphere head_framing(const PlacementFile& p, const HeadExtents& e) {
  check_transform(p.transform, "the placement's transform");
  const Eigen::Matrix3d linear = p.transform.block<3, 3>(0, 0);
  // Scene units per millimetre: the fit's metric estimate when it has one; a transform's axes carry
  // the frame's own stretch too, so they only stand in for a placement without the estimate.
  const double mean_axis = (linear.col(0).norm() + linear.col(1).norm() + linear.col(2).norm()) / 3.0;
  const double units_per_mm =
      p.mm_per_unit > 0.0 && std::isfinite(p.mm_per_unit) ? 1.0 / p.mm_per_unit : mean_axis;
  Eigen::Matrix3d axes;
  for (int c = 0; c < 3; ++c) axes.col(c) = linear.col(c).normalized();
  // The canonical origin is the nose bridge: about eye level, at the glabella's depth. Vertically the
  // head spans chin..crown around eye level; in depth its middle is half a head length behind the
  // glabella.
  const double top = e.vertex_above_eyes_mm, bottom = -e.chin_below_eyes_mm;
  const Eigen::Vector3d middle_mm(0.0, 0.5 * (top + bottom), -0.5 * e.head_length_mm);
  const Eigen::Vector3d center = p.transform.block<3, 1>(0, 3) + axes * middle_mm * units_per_mm;
  render::FramedSphere s;
  s.center = {float(center.x()), float(center.y()), float(center.z())};
  s.radius = float(0.5 * (top - bottom) * units_per_mm);
  return s;
}

render::Vec3 head_front(const PlacementFile& p) {
  check_transform(p.transform, "the placement's transform");
  const Eigen::Vector3d z = p.transform.block<3, 1>(0, 2).normalized();
  return {float(z.x()), float(z.y()), float(z.z())};
}

}  // namespace lorgnette::fit
