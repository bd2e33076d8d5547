// Frame measurements on canonical meshes; see frame_metrics.h.
#include "mesh/frame_metrics.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>

#include "mesh/canonical.h"
#include "mesh/temple_bend.h"

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

// The back of the front at one hinge: the rearmost frame sample near the coarse hinge depth that
// lies outside the temple's vertical band (the rim or endpiece, not the temple itself). The coarse
// hinge is the back of the last tall 0.5 mm depth bin (temple_bend.h), up to a bin behind the face.
double refined_hinge_z(const std::vector<Eigen::Vector3f>& pts, const Eigen::Vector3d& hinge, double width) {
  const int s = hinge.x() > 0 ? 1 : -1;
  std::vector<float> ys;
  for (const auto& p : pts)
    if (s * p.x() > 0.25 * width && p.z() < hinge.z() && p.z() > hinge.z() - 6.0) ys.push_back(p.y());
  if (ys.size() < 10) return hinge.z();
  std::sort(ys.begin(), ys.end());
  const float lo = ys[ys.size() / 50] - 0.5f, hi = ys[ys.size() - 1 - ys.size() / 50] + 0.5f;
  double z = hinge.z() + 1.0;  // the search window: the coarse bin and the next
  for (const auto& p : pts)
    if (s * p.x() > 0.25 * width && (p.y() < lo || p.y() > hi) && p.z() >= hinge.z() && p.z() < z) z = p.z();
  return z < hinge.z() + 1.0 ? z : hinge.z();
}

// Length along one temple's centre line from `start` (the hinge) to the end of its tip, the bend
// included. The line is tracked: from the current point, the centroid of the temple samples in the
// next kSlab mm along the current direction (within kRadius of it) is the next point. Each step
// counts its advance along the direction, so sampling noise across the temple adds no length. The
// direction follows the step (a bend of any angle is followed) when the step is a full slab's (its
// centroid about half a slab ahead); shorter steps, at bulky hinge hardware or where the slab holds
// the tip's end, keep it. At the tip the steps shrink geometrically until the slab is empty; the
// rest is the farthest sample along the direction (on a tip cut square to the temple, its end face).
float temple_centreline_length(const std::vector<Eigen::Vector3f>& pts, const Eigen::Vector3d& start) {
  constexpr double kSlab = 4.0, kRadius = 12.0;
  const int s = start.x() > 0 ? 1 : -1;
  std::vector<Eigen::Vector3d> temple;  // the side's samples behind the hinge, nose pads excluded
  for (const auto& p : pts)
    if (s * p.x() > 0.5 * s * start.x() && p.z() < start.z()) temple.push_back(p.cast<double>());
  Eigen::Vector3d p = start, d(0.0, 0.0, -1.0);
  auto ahead = [&](const Eigen::Vector3d& q, double* t) {
    *t = (q - p).dot(d);
    return *t > 0.0 && ((q - p) - *t * d).norm() < kRadius;
  };
  double len = 0.0;
  int steps = 0;
  while (steps < 1000) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int n = 0;
    double t;
    for (const auto& q : temple)
      if (ahead(q, &t) && t <= kSlab) sum += q, ++n;
    if (n < 10) break;
    const Eigen::Vector3d c = sum / n;
    const double advance = (c - p).dot(d);
    len += advance;
    if (advance > 0.35 * kSlab) d = (c - p).normalized();
    p = c;
    ++steps;
  }
  if (steps == 0) return 0.0f;  // no temple behind the hinge
  double tip = 0.0, t;
  for (const auto& q : temple)
    if (ahead(q, &t)) tip = std::max(tip, t);
  return static_cast<float>(len + tip);
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
    lens[i] =
        std::find(m.lens_parts.begin(), m.lens_parts.end(), mesh.triangle_part[i]) != m.lens_parts.end();
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
    m.lens_centre_y_mm = 0.5f * (left.center().y() + right.center().y());
  }
  lens.flip();
  m.hinges = detect_temple_hinges(mesh, &m.no_hinges);
  // Dense samples: the temple's centre line is tracked through centroids of 4 mm slabs of it.
  std::vector<Eigen::Vector3f> pts = sample_surface(mesh, 160000, 13u, &lens);
  if (pts.empty()) return m;
  if (m.hinges) {
    float sum = 0.0f;
    int sides = 0;
    for (Eigen::Vector3d h : {m.hinges->left, m.hinges->right}) {
      h.z() = refined_hinge_z(pts, h, m.total_width_mm);
      float len = temple_centreline_length(pts, h);
      if (len > 0.0f) sum += len, ++sides;
    }
    if (sides > 0) m.temple_length_mm = sum / sides;
  }
  return m;
}

}  // namespace lorgnette::mesh
