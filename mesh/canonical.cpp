// Orientation and unit detection for glasses meshes; see canonical.h.
#include "mesh/canonical.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

namespace lorgnette::mesh {
namespace {

constexpr double kAssumedWidthMm = 140.0;
constexpr double kMinWidthMm = 105.0, kMaxWidthMm = 185.0;  // adult frames, total width incl. temples

Eigen::AlignedBox3f bbox(const std::vector<Eigen::Vector3f>& pts) {
  Eigen::AlignedBox3f b;
  for (const auto& p : pts) b.extend(p);
  return b;
}

// Mean distance from each point to the nearest point of the set mirrored about the plane
// axis = centre (brute force on a few hundred points is fast enough and exact).
double mirror_error(const std::vector<Eigen::Vector3f>& pts, int axis, float centre) {
  double sum = 0.0;
  for (const auto& p : pts) {
    Eigen::Vector3f m = p;
    m[axis] = 2.0f * centre - m[axis];
    float best = std::numeric_limits<float>::max();
    for (const auto& q : pts) best = std::min(best, (q - m).squaredNorm());
    sum += std::sqrt(best);
  }
  return sum / std::max<size_t>(1, pts.size());
}

// +1 when the "front" (where geometry crosses the symmetry plane: the bridge) lies towards +axis.
int front_sign(const std::vector<Eigen::Vector3f>& pts, int x_axis, int z_axis,
               const Eigen::AlignedBox3f& b) {
  float cx = b.center()[x_axis], half = 0.06f * b.sizes()[x_axis];
  double sum = 0.0;
  int n = 0;
  for (const auto& p : pts)
    if (std::abs(p[x_axis] - cx) < half) sum += p[z_axis], ++n;
  double ref = b.center()[z_axis];
  if (n == 0) {  // rimless or bridge-less: the heavy front decides
    for (const auto& p : pts) sum += p[z_axis];
    n = static_cast<int>(pts.size());
  }
  return sum / n >= ref ? 1 : -1;
}

// +1 when the temples leave the front towards +axis (hinges sit in the upper part of the front).
int up_sign(const std::vector<Eigen::Vector3f>& pts, int y_axis, int z_axis, int zs,
            const Eigen::AlignedBox3f& b) {
  float depth = b.sizes()[z_axis];
  float front = zs > 0 ? b.max()[z_axis] : b.min()[z_axis];
  Eigen::AlignedBox<float, 1> front_y;
  double temple_sum = 0.0;
  int n = 0;
  for (const auto& p : pts) {
    float behind = zs * (front - p[z_axis]);  // distance behind the front plane
    if (behind < 0.1f * depth) front_y.extend(Eigen::Matrix<float, 1, 1>(p[y_axis]));
    if (behind > 0.15f * depth && behind < 0.45f * depth) temple_sum += p[y_axis], ++n;
  }
  if (n == 0 || front_y.isEmpty()) return 1;
  return temple_sum / n >= front_y.center()[0] ? 1 : -1;
}

}  // namespace

std::vector<Eigen::Vector3f> sample_surface(const TriMesh& mesh, int count, unsigned seed,
                                            const std::vector<bool>* mask) {
  std::vector<double> cdf;
  cdf.reserve(mesh.triangles.size());
  double total = 0.0;
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    bool use = mask == nullptr || (*mask)[i];
    if (use)
      total += 0.5 * (mesh.positions[t[1]] - mesh.positions[t[0]])
                         .cross(mesh.positions[t[2]] - mesh.positions[t[0]])
                         .norm();
    cdf.push_back(total);
  }
  std::vector<Eigen::Vector3f> out;
  if (total <= 0.0) return out;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  out.reserve(count);
  for (int i = 0; i < count; ++i) {
    size_t tri = std::lower_bound(cdf.begin(), cdf.end(), u01(rng) * total) - cdf.begin();
    tri = std::min(tri, cdf.size() - 1);
    float a = static_cast<float>(u01(rng)), b = static_cast<float>(u01(rng));
    if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
    const auto& t = mesh.triangles[tri];
    out.push_back(mesh.positions[t[0]] + a * (mesh.positions[t[1]] - mesh.positions[t[0]]) +
                  b * (mesh.positions[t[2]] - mesh.positions[t[0]]));
  }
  return out;
}

Canonicalization detect_canonical_frame(const TriMesh& mesh, double mm_override) {
  Canonicalization c;
  std::vector<Eigen::Vector3f> pts = sample_surface(mesh, 20000, 7u);
  std::vector<Eigen::Vector3f> few(pts.begin(), pts.begin() + std::min<size_t>(pts.size(), 700));
  Eigen::AlignedBox3f b = bbox(pts);
  // Symmetry axis: the file axis whose mirror image matches best (relative to the extent).
  int x_axis = 0;
  double best = std::numeric_limits<double>::max();
  for (int a = 0; a < 3; ++a) {
    double e = mirror_error(few, a, b.center()[a]) / std::max(1e-12f, b.sizes().norm());
    if (e < best) best = e, x_axis = a;
  }
  int o1 = (x_axis + 1) % 3, o2 = (x_axis + 2) % 3;
  int z_axis = b.sizes()[o1] >= b.sizes()[o2] ? o1 : o2;
  int y_axis = 3 - x_axis - z_axis;
  int zs = front_sign(pts, x_axis, z_axis, b);
  int ys = up_sign(pts, y_axis, z_axis, zs, b);
  Eigen::Vector3f ez = Eigen::Vector3f::Unit(z_axis) * static_cast<float>(zs);
  Eigen::Vector3f ey = Eigen::Vector3f::Unit(y_axis) * static_cast<float>(ys);
  Eigen::Vector3f ex = ey.cross(ez);  // right-handed: a proper rotation, never a mirror
  c.rotation.row(0) = ex;
  c.rotation.row(1) = ey;
  c.rotation.row(2) = ez;
  const char* names = "xyz";
  c.notes.push_back(
      fmt::format("orientation: canonical x = {}file {}, y = {}file {}, z = {}file {} "
                  "(symmetry plane, temples backwards, hinges up)",
                  ex[x_axis] > 0 ? "+" : "-", names[x_axis], ys > 0 ? "+" : "-", names[y_axis],
                  zs > 0 ? "+" : "-", names[z_axis]));
  double width = b.sizes()[x_axis];
  if (mm_override > 0) {
    c.mm_per_unit = mm_override;
    c.units = fmt::format("{} mm per unit (given)", mm_override);
  } else {
    c.mm_per_unit = 0.0;
    const std::pair<double, const char*> candidates[] = {{mesh.units_to_mm, "the file's declared unit"},
                                                         {1.0, "millimetres"},
                                                         {10.0, "centimetres"},
                                                         {1000.0, "metres"},
                                                         {25.4, "inches"}};
    for (const auto& [mm, name] : candidates)
      if (width * mm >= kMinWidthMm && width * mm <= kMaxWidthMm) {
        c.mm_per_unit = mm;
        c.units =
            fmt::format("{} ({} mm per unit; total width {:.1f} mm is plausible)", name, mm, width * mm);
        break;
      }
    if (c.mm_per_unit == 0.0) {
      c.mm_per_unit = kAssumedWidthMm / width;
      c.units = fmt::format(
          "unknown: no common unit gives a plausible width, assumed a total width of {:.0f} mm "
          "({:.4g} mm per unit); pass --mm-per-unit or a sidecar to override",
          kAssumedWidthMm, c.mm_per_unit);
    }
  }
  c.notes.push_back("units: " + c.units);
  float s = static_cast<float>(c.mm_per_unit);
  Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
  m.topLeftCorner<3, 3>() = s * c.rotation;
  m.block<3, 1>(0, 3) = -s * (c.rotation * b.center());
  c.file_to_canonical = m;
  c.symmetry_error_mm = best * b.sizes().norm() * c.mm_per_unit;
  return c;
}

void transform_mesh(TriMesh& mesh, const Eigen::Matrix4f& transform) {
  Eigen::Affine3f xf(transform);
  Eigen::Matrix3f nxf = xf.linear().inverse().transpose();
  for (auto& p : mesh.positions) p = xf * p;
  for (auto& n : mesh.normals) n = (nxf * n).normalized();
  // A mirroring transform flips the winding; swap two indices so geometric normals stay outward.
  if (xf.linear().determinant() < 0)
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
}

}  // namespace lorgnette::mesh
