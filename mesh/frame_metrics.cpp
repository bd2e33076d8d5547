// Frame measurements on canonical meshes; see frame_metrics.h.
#include "mesh/frame_metrics.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <Eigen/Geometry>

#include "mesh/canonical.h"

namespace lorgnette::mesh {
namespace {

// Parts made mostly of lens material that are also lens-sized: at least 22 % of the frame width
// (a transparent nose-pad pair shares the lens material flags but spans ~14 %; lenses span 30 %+).
std::vector<int> find_lens_parts(const TriMesh& mesh, float total_width) {
  std::vector<bool> lens = lens_triangles(mesh);
  std::map<int, std::pair<int, int>> count;  // part -> (lens triangles, all)
  std::map<int, Eigen::AlignedBox3f> box;
  for (size_t i = 0; i < lens.size() && i < mesh.triangle_part.size(); ++i) {
    auto& c = count[mesh.triangle_part[i]];
    c.first += lens[i];
    c.second++;
    for (int k = 0; k < 3; ++k) box[mesh.triangle_part[i]].extend(mesh.positions[mesh.triangles[i][k]]);
  }
  std::vector<int> out;
  for (const auto& [part, c] : count)
    if (2 * c.first > c.second && box[part].sizes().x() >= 0.22f * total_width) out.push_back(part);
  return out;
}

float temple_arc_length(const std::vector<Eigen::Vector3f>& pts, float width, float front) {
  const float start = front - 12.0f, bin = 4.0f;
  std::map<int, std::pair<Eigen::Vector3f, int>> bins;
  for (const auto& p : pts)
    if (p.x() > 0.3f * width && p.z() < start) {
      auto& b = bins[static_cast<int>((start - p.z()) / bin)];
      if (b.second == 0) b.first.setZero();
      b.first += p, b.second++;
    }
  float len = 0.0f;
  Eigen::Vector3f prev;
  bool first = true;
  for (auto& [k, b] : bins) {
    if (b.second < 3) continue;
    Eigen::Vector3f c = b.first / static_cast<float>(b.second);
    len += first ? std::abs(start - c.z()) + 12.0f : (c - prev).norm();
    prev = c;
    first = false;
  }
  return len;
}

}  // namespace

FrameMetrics measure_frame(const TriMesh& mesh) {
  FrameMetrics m;
  Eigen::AlignedBox3f all;
  for (const auto& p : mesh.positions) all.extend(p);
  m.total_width_mm = all.sizes().x();
  m.total_height_mm = all.sizes().y();
  m.total_depth_mm = all.sizes().z();
  m.lens_parts = find_lens_parts(mesh, m.total_width_mm);
  std::vector<bool> lens(mesh.triangles.size(), false);
  for (size_t i = 0; i < lens.size() && i < mesh.triangle_part.size(); ++i)
    lens[i] = std::find(m.lens_parts.begin(), m.lens_parts.end(), mesh.triangle_part[i]) != m.lens_parts.end();
  Eigen::AlignedBox3f left, right;
  for (size_t i = 0; i < lens.size(); ++i)
    if (lens[i])
      for (int k = 0; k < 3; ++k) {
        const auto& p = mesh.positions[mesh.triangles[i][k]];
        (p.x() >= 0 ? left : right).extend(p);
      }
  if (!left.isEmpty() && !right.isEmpty()) {
    m.lens_width_mm = 0.5f * (left.sizes().x() + right.sizes().x());
    m.lens_height_mm = 0.5f * (left.sizes().y() + right.sizes().y());
    m.bridge_mm = std::max(0.0f, left.min().x() - right.max().x());
  }
  lens.flip();
  std::vector<Eigen::Vector3f> pts = sample_surface(mesh, 40000, 13u, &lens);
  if (!pts.empty()) m.temple_length_mm = temple_arc_length(pts, m.total_width_mm, all.max().z());
  return m;
}

}  // namespace lorgnette::mesh
