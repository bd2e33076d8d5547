// load_glasses: load, canonicalise, reference points (sidecar or detection), measure; see glasses.h.
#include "mesh/glasses.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <Eigen/Geometry>

#include "host/util/bounds.h"

namespace lorgnette::mesh {
namespace {

Eigen::Vector3f apply(const Eigen::Matrix4f& m, const Eigen::Vector3f& p) {
  return m.topLeftCorner<3, 3>() * p + m.block<3, 1>(0, 3);
}

}  // namespace

Glasses canonicalize_glasses(TriMesh mesh, const GlassesOptions& options, const RefPointsSidecar* sidecar) {
  check_bound_or_zero(bounds::kMmPerUnit, options.mm_per_unit);  // 0: detect; never a negative or NaN
  Glasses g;
  double mm_override = options.mm_per_unit > 0 ? options.mm_per_unit : sidecar ? sidecar->mm_per_unit : 0.0;
  g.canonical = detect_canonical_frame(mesh, mm_override);
  transform_mesh(mesh, g.canonical.file_to_canonical);
  if (sidecar) {
    g.ref = sidecar->points;
    g.ref.g_c = apply(g.canonical.file_to_canonical, g.ref.g_c);
    g.ref.g_l = apply(g.canonical.file_to_canonical, g.ref.g_l);
    g.ref.g_r = apply(g.canonical.file_to_canonical, g.ref.g_r);
  } else {
    g.ref = detect_refpoints(mesh);
  }
  // Move the origin to g_c.
  Eigen::Matrix4f shift = Eigen::Matrix4f::Identity();
  shift.block<3, 1>(0, 3) = -g.ref.g_c;
  transform_mesh(mesh, shift);
  g.canonical.file_to_canonical = shift * g.canonical.file_to_canonical;
  g.ref.g_l -= g.ref.g_c;
  g.ref.g_r -= g.ref.g_c;
  g.ref.g_c.setZero();
  mesh.units_to_mm = 1.0;
  g.metrics = measure_frame(mesh);
  g.mesh = std::move(mesh);
  for (const auto& n : g.canonical.notes) g.notes.push_back(n);
  for (const auto& n : g.ref.notes) g.notes.push_back(n);
  if (g.ref.g_l.x() <= 0 || g.ref.g_r.x() >= 0)
    g.notes.push_back("warning: g_l should lie at x > 0 (wearer's left) and g_r at x < 0; check the sidecar");
  return g;
}

Glasses load_glasses(const std::string& path, const GlassesOptions& options) {
  check_bound_or_zero(bounds::kMmPerUnit, options.mm_per_unit);  // before the (slow) load
  LoadReport report;
  TriMesh mesh = load_mesh(path, options.load, &report);
  std::optional<RefPointsSidecar> sidecar;
  if (options.use_sidecar) sidecar = read_refpoints_sidecar(path);
  if (sidecar) spdlog::info("reference points from {}", sidecar_path(path));
  Glasses g = canonicalize_glasses(std::move(mesh), options, sidecar ? &*sidecar : nullptr);
  g.path = path;
  g.notes.insert(g.notes.begin(), report.warnings.begin(), report.warnings.end());
  return g;
}

}  // namespace lorgnette::mesh
