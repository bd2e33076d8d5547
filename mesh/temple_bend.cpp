// Temple spread on meshes and hinge detection on canonical frames (see temple_bend.h).
#include "mesh/temple_bend.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <map>

#include "mesh/frame_samples.h"

namespace lorgnette::mesh {
namespace {

double quantile(std::vector<double> v, double q) {
  size_t k = std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

// Hinge of one side (s = +1 left, -1 right) from frame surface samples; nullopt when none.
std::optional<Eigen::Vector3d> side_hinge(const std::vector<Eigen::Vector3f>& pts, double width, double front,
                                          int s, std::string* why) {
  const double bin = 0.5, run_mm = 5.0, temple_mm = 6.0;
  std::map<int, std::vector<double>> ys;  // bin k covers z in (front - (k+1) bin, front - k bin]
  for (const auto& p : pts)
    if (s * p.x() > 0.25 * width) ys[static_cast<int>((front - p.z()) / bin)].push_back(p.y());
  std::map<int, double> extent;
  double tallest = 0.0;
  for (auto& [k, v] : ys) {
    if (v.size() < 3) continue;
    extent[k] = quantile(v, 0.98) - quantile(v, 0.02);
    tallest = std::max(tallest, extent[k]);
  }
  const int run = static_cast<int>(run_mm / bin);
  for (auto it = extent.begin(); it != extent.end(); ++it) {
    int k = it->first, low = 0;
    for (int j = k; j < k + run; ++j) {
      auto e = extent.find(j);
      if (e == extent.end() || e->second >= 0.4 * tallest) break;
      ++low;
    }
    if (low < run || it == extent.begin()) continue;
    const double z = front - k * bin;
    std::vector<double> xs, yv;
    for (const auto& p : pts)
      if (s * p.x() > 0.25 * width && p.z() <= z && p.z() > z - temple_mm)
        xs.push_back(p.x()), yv.push_back(p.y());
    return Eigen::Vector3d(quantile(xs, 0.5), quantile(yv, 0.5), z);
  }
  if (why)
    *why = fmt::format("no temple found on the {} side (no thin section behind the front)",
                       s > 0 ? "left" : "right");
  return std::nullopt;
}

}  // namespace

void bend_mesh(const TempleBend& b, TriMesh& mesh) {
  if (!b.active()) return;
  const bool normals = mesh.normals.size() == mesh.positions.size();
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const Eigen::Vector3d p = mesh.positions[i].cast<double>();
    mesh.positions[i] = bend_point(b, p).cast<float>();
    if (normals) mesh.normals[i] = bend_normal(b, p, mesh.normals[i].cast<double>()).cast<float>();
  }
}

std::optional<TempleHinges> detect_temple_hinges(const TriMesh& mesh, std::string* why) {
  std::vector<Eigen::Vector3f> pts = sample_frame_surface(mesh, 80000, 17u);
  if (pts.size() < 100) {
    if (why) *why = "the frame has too little surface to find its temples";
    return std::nullopt;
  }
  Eigen::AlignedBox3f box;
  for (const auto& p : pts) box.extend(p);
  const double width = box.sizes().x(), front = box.max().z();
  auto l = side_hinge(pts, width, front, +1, why);
  auto r = side_hinge(pts, width, front, -1, why);
  if (!l || !r) return std::nullopt;
  // Mirror-symmetric, like the reference points: average the left with the mirrored right.
  Eigen::Vector3d m(-r->x(), r->y(), r->z());
  TempleHinges h;
  h.left = 0.5 * (*l + m);
  h.right = Eigen::Vector3d(-h.left.x(), h.left.y(), h.left.z());
  return h;
}

}  // namespace lorgnette::mesh
