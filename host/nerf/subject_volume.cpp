// The subject's volume and its occupancy mask; see subject_volume.h.
#include "host/nerf/subject_volume.h"

#include <cmath>

#include "host/nerf/occupancy_cells.h"
#include "kernels/train/occupancy.h"

namespace lorgnette::nerf {

Vec3f OrientedShape::local(const Vec3f& p) const {
  const float d[3] = {p[0] - center[0], p[1] - center[1], p[2] - center[2]};
  Vec3f q;
  for (int a = 0; a < 3; ++a) q[a] = axes[a][0] * d[0] + axes[a][1] * d[1] + axes[a][2] * d[2];
  return q;
}

bool OrientedShape::contains(const Vec3f& p) const {
  const Vec3f q = local(p);
  if (q[1] < y_from * half[1]) return false;
  if (kind == Kind::Box)
    return std::fabs(q[0]) <= half[0] && std::fabs(q[1]) <= half[1] && std::fabs(q[2]) <= half[2];
  if (kind == Kind::Cylinder && std::fabs(q[1]) > half[1]) return false;
  float s = 0.0f;
  for (int a = 0; a < 3; ++a) {
    if (kind == Kind::Cylinder && a == 1) continue;
    if (!(half[a] > 0.0f)) return false;
    s += (q[a] / half[a]) * (q[a] / half[a]);
  }
  return s <= 1.0f;
}

OrientedShape OrientedShape::grown(float d) const {
  OrientedShape s = *this;
  for (float& h : s.half) h += d;
  return s;
}

bool SubjectVolume::contains(const Vec3f& p) const {
  if (clip && !clip->contains(p)) return false;
  for (const OrientedShape& s : parts)
    if (s.contains(p)) return true;
  return false;
}

SubjectVolume SubjectVolume::grown(float d) const {
  SubjectVolume v = *this;
  for (OrientedShape& s : v.parts) s = s.grown(d);
  if (v.clip) v.clip = v.clip->grown(d);
  return v;
}

std::vector<uint32_t> volume_occupancy_mask(const SubjectVolume& volume, const Aabb& box, uint32_t res) {
  return occupancy_mask_where<float>(box, res, [&](const float* p) {
    return volume.contains(Vec3f{p[0], p[1], p[2]});
  });
}

std::vector<uint32_t> room_cutout_mask(const Aabb& room, const SubjectVolume& volume, float margin,
                                       const SubjectVolume& body, uint32_t res) {
  const SubjectVolume cut = volume.grown(margin);
  std::vector<uint32_t> mask(occ_word_count(res), 0u);
  for (uint32_t z = 0; z < res; ++z)
    for (uint32_t y = 0; y < res; ++y)
      for (uint32_t x = 0; x < res; ++x) {
        const uint32_t idx[3] = {x, y, z};
        Vec3f p;
        for (int a = 0; a < 3; ++a) p[a] = room.min[a] + (float(idx[a]) + 0.5f) / float(res) * room.extent(a);
        const uint32_t cell = x + res * (y + res * z);
        if (!cut.contains(p) || body.contains(p)) mask[cell >> 5] |= 1u << (cell & 31u);
      }
  return mask;
}

SolidHull convex_part_hull(const OrientedShape& e, const std::string& name, int rings, int segments) {
  SolidHull h;
  h.name = name;
  h.convex_solid = true;
  h.max_view_deg = 180.0f;
  h.facing = e.axes[2];
  auto at = [&](double x, double y, double z) {
    const double u[3] = {x, y, z};
    Vec3f p = e.center;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) p[b] += float(u[a] * e.half[a]) * e.axes[a][b];
    h.points.push_back(p);
  };
  if (e.kind == OrientedShape::Kind::Cylinder) {
    for (double y : {-1.0, 1.0})
      for (int k = 0; k < segments; ++k) {
        const double ph = 2.0 * M_PI * k / segments;
        at(std::cos(ph), y, std::sin(ph));
      }
    return h;
  }
  at(0.0, 1.0, 0.0), at(0.0, -1.0, 0.0);
  for (int r = 1; r <= rings; ++r) {
    const double th = M_PI * r / (rings + 1);
    for (int k = 0; k < segments; ++k) {
      const double ph = 2.0 * M_PI * k / segments;
      at(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph));
    }
  }
  return h;
}

uint64_t mask_count(const std::vector<uint32_t>& mask) {
  uint64_t n = 0;
  for (uint32_t w : mask) n += static_cast<uint64_t>(__builtin_popcount(w));
  return n;
}

}  // namespace lorgnette::nerf
