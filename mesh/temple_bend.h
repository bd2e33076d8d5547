// Temple spread: how the rigid frame's temples (arms) flex outwards at the hinges when the head is
// wider than the frame (real temples spring open; opticians also bend them). Per side (left = the
// wearer's left, x > 0; right x < 0) a hinge point in canonical mm and a spread angle about the
// frame's vertical axis (canonical +y) through the hinge, + = outwards (away from the head).
//
// The deformation of a canonical point p on side s (s = +1 when p.x > 0, -1 otherwise):
// - it belongs to the temple when it lies behind the hinge (p.z < hinge.z) and is further out than
//   half the hinge's distance from the symmetry plane (s * p.x > 0.5 * s * hinge.x; keeps the nose
//   pads, which also sit behind the front, rigid). Everything else is unchanged;
// - a temple point at depth d = hinge.z - p.z behind the hinge turns by w(d) * spread about the
//   vertical axis through the hinge, w = smoothstep(d / ramp_mm): 0 at the hinge, 1 from ramp_mm
//   back, C1 in between, so the mesh does not tear at the hinge and points far behind turn by
//   exactly the spread angle.
// Normals transform with the exact inverse transpose of the map's Jacobian (the ramp's twist
// included). The math is header-only (Eigen) so the fit (point samples) and the renderer (meshes,
// temple_bend.cpp) run the very same function. placement.json's "temples" object, which carries it,
// is read and written by the placement module (fit/placement_json.h).
#pragma once
#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "mesh/trimesh.h"

namespace lorgnette::mesh {

struct TempleSide {
  Eigen::Vector3d hinge{0, 0, 0};  // canonical mm
  double spread_deg = 0.0;         // + = outwards
};

struct TempleBend {
  TempleSide left, right;  // left: x > 0
  double ramp_mm = 4.0;    // length of the smooth transition behind each hinge
  bool active() const { return left.spread_deg != 0.0 || right.spread_deg != 0.0; }
};

// +1 when canonical point p belongs to the left temple, -1 for the right one, 0 when it is rigid
// (ahead of its side's hinge, or nearer the symmetry plane than half the hinge's x).
inline int temple_side(const TempleBend& b, const Eigen::Vector3d& p) {
  const int s = p.x() > 0.0 ? 1 : -1;
  const TempleSide& t = s > 0 ? b.left : b.right;
  return t.hinge.z() - p.z() > 0.0 && s * p.x() > 0.5 * s * t.hinge.x() ? s : 0;
}

namespace temple_detail {

// Side, ramp weight and its derivative along z for a point; false when the point does not move.
inline bool temple_weight(const TempleBend& b, const Eigen::Vector3d& p, const TempleSide** side, double* w,
                          double* dw_dz) {
  const int s = temple_side(b, p);
  if (s == 0) return false;
  const TempleSide& t = s > 0 ? b.left : b.right;
  *side = &t;
  if (t.spread_deg == 0.0) return false;
  const double d = t.hinge.z() - p.z(), ramp = std::max(b.ramp_mm, 1e-9), u = std::min(d / ramp, 1.0);
  *w = u * u * (3.0 - 2.0 * u);                           // smoothstep
  *dw_dz = d < ramp ? -6.0 * u * (1.0 - u) / ramp : 0.0;  // d/dz = -d/dd
  return true;
}

// Rotation about +y by the signed angle that turns the temple of `side` outwards by `deg`.
// The temple runs along -z from the hinge; outwards = +x on the left: angle -deg about +y there.
inline double signed_angle_rad(const TempleBend& b, const TempleSide* side, double deg) {
  return (side == &b.left ? -1.0 : 1.0) * deg * M_PI / 180.0;
}

}  // namespace temple_detail

// The deformed position of a canonical point.
inline Eigen::Vector3d bend_point(const TempleBend& b, const Eigen::Vector3d& p) {
  const TempleSide* side;
  double w, dw;
  if (!temple_detail::temple_weight(b, p, &side, &w, &dw)) return p;
  const double a = temple_detail::signed_angle_rad(b, side, w * side->spread_deg);
  const Eigen::Vector3d r = p - side->hinge;
  const double c = std::cos(a), s = std::sin(a);
  return side->hinge + Eigen::Vector3d(c * r.x() + s * r.z(), r.y(), -s * r.x() + c * r.z());
}

inline Eigen::Vector3f bend_point(const TempleBend& b, const Eigen::Vector3f& p) {
  return bend_point(b, Eigen::Vector3d(p.cast<double>())).cast<float>();
}

// The deformed normal (unit) of a surface with normal n at canonical point p: J^-T n, normalised.
inline Eigen::Vector3d bend_normal(const TempleBend& b, const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
  const TempleSide* side;
  double w, dw;
  if (!temple_detail::temple_weight(b, p, &side, &w, &dw)) return n;
  const double a = temple_detail::signed_angle_rad(b, side, w * side->spread_deg);
  const double da_dz = temple_detail::signed_angle_rad(b, side, dw * side->spread_deg);
  const Eigen::Vector3d r = p - side->hinge;
  const double c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d j;
  j << c, 0, s, 0, 1, 0, -s, 0, c;                                                   // rotation part
  const Eigen::Vector3d dq_da(-s * r.x() + c * r.z(), 0.0, -c * r.x() - s * r.z());  // d(R r)/da
  j.col(2) += dq_da * da_dz;                                                         // the ramp's twist
  Eigen::Vector3d out = j.inverse().transpose() * n;
  double len = out.norm();
  return len > 0.0 ? Eigen::Vector3d(out / len) : n;
}

// Deforms positions and (when present) normals of a canonical-mm mesh in place.
void bend_mesh(const TempleBend& b, TriMesh& mesh);

// Deformed copies of canonical points (the fit's frame samples).
inline std::vector<Eigen::Vector3d> bend_points(const TempleBend& b,
                                                const std::vector<Eigen::Vector3d>& pts) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(pts.size());
  for (const auto& p : pts) out.push_back(bend_point(b, p));
  return out;
}

// Hinges found on a canonical-mm frame: per side, walking back from the front face, the first
// depth where the frame's cross-section on that side (|x| > 25 % of the width) stops being as tall
// as a rim (vertical extent below 40 % of the front's) and stays low for 5 mm: the temple alone.
// The hinge is at that depth, at the median x and y of the first 6 mm of temple. Made mirror-
// symmetric like the reference points. nullopt (with the reason in `why`) when no temple is found.
struct TempleHinges {
  Eigen::Vector3d left{0, 0, 0}, right{0, 0, 0};
};
std::optional<TempleHinges> detect_temple_hinges(const TriMesh& canonical_mesh, std::string* why = nullptr);

}  // namespace lorgnette::mesh
