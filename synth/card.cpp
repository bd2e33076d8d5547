// The held card and the finger; see card.h. The card's texture is drawn in millimetres of the card
// (x from its left edge, y down from its top edge) at kTexelsPerMm, so its features are exact sizes.
#include "synth/card.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "mesh/embree_scene.h"

namespace lorgnette::synth {
namespace {

using V3 = Eigen::Vector3f;
constexpr float kTexelsPerMm = 6.0f;
constexpr float kFingerRadiusMm = 8.0f;

bool inside(float x, float y, float x0, float y0, float x1, float y1) {
  return x >= x0 && x <= x1 && y >= y0 && y <= y1;
}

// A pale body with a colour gradient, a dark brand block, a gold chip with contacts, a card number
// and a name in dark blocks, and a logo of two discs: the edges any card's printing has.
V3 card_colour(float x, float y) {
  const V3 navy(0.02f, 0.04f, 0.12f), gold(0.55f, 0.40f, 0.12f);
  V3 c = V3(0.78f, 0.80f, 0.84f) + (x / kCardWidthMm) * V3(-0.10f, -0.04f, 0.02f);
  if (inside(x, y, 7, 6, 40, 13)) c = navy;
  if (inside(x, y, 10, 19, 22, 28)) {
    c = gold;
    if (std::abs(y - 23.5f) < 0.3f || std::abs(x - 16.0f) < 0.3f) c *= 0.5f;
  }
  if (inside(x, y, 8, 35, 78, 39.5f) && std::fmod(x - 8.0f, 17.5f) < 15.0f &&
      std::fmod(x - 8.0f, 3.75f) < 3.0f)
    c = navy;
  if (inside(x, y, 8, 43.5f, 50, 46.5f) && std::fmod(x - 8.0f, 2.6f) < 2.0f) c = navy;
  for (float cx : {64.0f, 72.0f})
    if (std::hypot(x - cx, y - 44.0f) < 5.5f) c = cx < 70 ? V3(0.60f, 0.05f, 0.04f) : V3(0.75f, 0.45f, 0.02f);
  return c;
}

Image card_texture() {
  const int w = int(kCardWidthMm * kTexelsPerMm), h = int(kCardHeightMm * kTexelsPerMm);
  Image img(w, h, 3);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      V3 c = card_colour((i + 0.5f) * kCardWidthMm / w, (j + 0.5f) * kCardHeightMm / h);
      for (int k = 0; k < 3; ++k) img.pixels[(size_t(j) * w + i) * 3 + k] = c[k];
    }
  return img;
}

// Least-squares plane z = a x + b y + c through the points.
Eigen::Vector3f fit_plane(const std::vector<V3>& pts) {
  Eigen::MatrixXf A(pts.size(), 3);
  Eigen::VectorXf z(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) A.row(i) << pts[i].x(), pts[i].y(), 1.0f, z[i] = pts[i].z();
  return A.colPivHouseholderQr().solve(z);
}

mesh::Material plain_material(const char* name, const V3& colour, int texture) {
  mesh::Material m;
  m.name = name;
  m.base_color = colour;
  m.roughness = 0.5f;
  m.base_color_texture = texture;
  return m;
}

// The card resting on the surface in front of it: centred on x = `x_mid` with its lower edge at
// y = `lower_y`, its plane fitted to the surface under it (rays along -z from z = `front_z`) and moved
// forward until the whole surface under the card lies behind it (the card rests on its bumps).
HeldCard card_resting_on(const mesh::EmbreeScene& scene, float x_mid, float lower_y, float front_z) {
  const float hw = 0.5f * kCardWidthMm, hh = 0.5f * kCardHeightMm, yc = lower_y + hh;
  std::vector<V3> under;
  for (int j = 0; j <= 6; ++j)
    for (int i = 0; i <= 8; ++i) {
      V3 o(x_mid - hw + kCardWidthMm * i / 8, yc - hh + kCardHeightMm * j / 6, front_z);
      mesh::Hit h = scene.intersect(o, V3(0, 0, -1));
      if (!h.hit)
        throw std::runtime_error(
            fmt::format("card: the head has no forehead at ({:.0f}, {:.0f}) mm", o.x(), o.y()));
      under.push_back(h.position);
    }
  Eigen::Vector3f abc = fit_plane(under);
  float lift = 0.0f;
  for (const V3& p : under) lift = std::max(lift, p.z() - (abc[0] * p.x() + abc[1] * p.y() + abc[2]));
  const float c = abc[2] + lift + 0.5f;
  V3 u = V3(1, 0, abc[0]).normalized();
  V3 v = V3(0, 1, abc[1]);
  v = (v - v.dot(u) * u).normalized();
  HeldCard card;
  card.normal = u.cross(v);
  V3 centre(x_mid, yc, abc[0] * x_mid + abc[1] * yc + c);
  card.corners = {centre - hw * u + hh * v, centre + hw * u + hh * v, centre + hw * u - hh * v,
                  centre - hw * u - hh * v};
  return card;
}

// The most forward point of the scene seen from the front: rays along -z on a 2 mm grid over its
// bounds (the nose tip of a head or a bust facing +z).
V3 most_forward_point(const mesh::EmbreeScene& scene) {
  const Eigen::AlignedBox3f box = scene.bounds();
  std::vector<mesh::RayQuery> rays;
  for (float y = box.min().y(); y <= box.max().y(); y += 2.0f)
    for (float x = box.min().x(); x <= box.max().x(); x += 2.0f)
      rays.push_back({V3(x, y, box.max().z() + 10.0f), V3(0, 0, -1)});
  V3 best(0, 0, -INFINITY);
  for (const mesh::Hit& h : scene.intersect_many(rays))
    if (h.hit && h.position.z() > best.z()) best = h.position;
  if (!std::isfinite(best.z())) throw std::runtime_error("card: the head mesh has no surface facing +z");
  return best;
}

// The midline x = `x` seen from the front, y from `y0` up in 0.5 mm steps over `length` mm.
std::vector<V3> midline(const mesh::EmbreeScene& scene, float x, float y0, float length) {
  const float front = scene.bounds().max().z() + 10.0f;
  std::vector<V3> points;
  for (float y = y0; y <= y0 + length; y += 0.5f) {
    mesh::Hit h = scene.intersect(V3(x, y, front), V3(0, 0, -1));
    if (!h.hit)
      throw std::runtime_error(
          fmt::format("card: the head's midline has a hole at y = {:.0f} mm (not a head facing +z?)", y));
    points.push_back(h.position);
  }
  return points;
}

// midline_profile (card.h) on a scene in millimetres. The sellion is the lowest point of the midline
// above the tip before it rises again by kRiseMm (the brow in front of the bridge); the glabella is
// the most forward point within kBrowMm above the sellion.
MidlineProfile profile_of(const mesh::EmbreeScene& scene) {
  constexpr float kBridgeMm = 80.0f, kBrowMm = 35.0f, kRiseMm = 1.0f;
  MidlineProfile p;
  p.nose_tip = most_forward_point(scene);
  const std::vector<V3> line = midline(scene, p.nose_tip.x(), p.nose_tip.y(), kBridgeMm + kBrowMm);
  size_t low = 0, rise = 0;
  for (size_t i = 1; i < line.size() && line[i].y() <= p.nose_tip.y() + kBridgeMm && !rise; ++i) {
    if (line[i].z() < line[low].z()) low = i;
    if (line[i].z() > line[low].z() + kRiseMm) rise = i;
  }
  if (!rise || low == 0)
    throw std::runtime_error(fmt::format(
        "card: no nose bridge and brow above the most forward point ({:.0f}, {:.0f}, {:.0f}) mm: the "
        "mesh must be a head facing +z with +y up",
        p.nose_tip.x(), p.nose_tip.y(), p.nose_tip.z()));
  p.sellion = p.glabella = line[low];
  for (size_t i = low; i < line.size() && line[i].y() <= p.sellion.y() + kBrowMm; ++i)
    if (line[i].z() > p.glabella.z()) p.glabella = line[i];
  return p;
}

}  // namespace

HeldCard card_on_forehead(const mesh::TriMesh& head, float above_eyes_mm) {
  mesh::EmbreeScene scene(head);
  return card_resting_on(scene, 0.0f, above_eyes_mm, 400.0f);
}

MidlineProfile midline_profile(const mesh::TriMesh& head, const Eigen::Matrix4f& to_mm) {
  return profile_of(mesh::EmbreeScene(head, to_mm));
}

HeldCard card_on_scanned_forehead(const mesh::TriMesh& head, const Eigen::Matrix4f& to_mm,
                                  float above_glabella_mm) {
  mesh::EmbreeScene scene(head, to_mm);
  const MidlineProfile p = profile_of(scene);
  return card_resting_on(scene, p.nose_tip.x(), p.glabella.y() + above_glabella_mm,
                         scene.bounds().max().z() + 10.0f);
}

mesh::TriMesh card_mesh(const HeldCard& card) {
  mesh::TriMesh m;
  m.positions.assign(card.corners.begin(), card.corners.end());
  m.normals.assign(4, card.normal);
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 3, 2}, {0, 2, 1}};  // counter-clockwise seen from the front
  m.textures.push_back(card_texture());
  m.materials.push_back(plain_material("id1_card", V3(1, 1, 1), 0));
  m.triangle_material.assign(2, 0);
  m.triangle_part.assign(2, 0);
  m.part_names = {"card"};
  return m;
}

mesh::TriMesh finger_mesh(const HeldCard& card, FingerPlacement where) {
  const V3 c = card.centre(), u = (card.corners[1] - card.corners[0]).normalized(),
           v = (card.corners[0] - card.corners[3]).normalized(), n = card.normal;
  // Base and tip in card millimetres from its centre (x right, y up); the finger comes from below.
  const float hw = 0.5f * kCardWidthMm, hh = 0.5f * kCardHeightMm;
  Eigen::Vector2f base = where == FingerPlacement::LowerEdge ? Eigen::Vector2f(-25, -hh - 55)
                                                             : Eigen::Vector2f(hw + 30, -hh - 45);
  Eigen::Vector2f tip = where == FingerPlacement::LowerEdge ? Eigen::Vector2f(-15, -hh + 18)
                                                            : Eigen::Vector2f(hw - 14, -hh + 12);
  auto at = [&](const Eigen::Vector2f& q) {
    return V3(c + q.x() * u + q.y() * v + (kFingerRadiusMm + 0.5f) * n);
  };
  const V3 p0 = at(base), p1 = at(tip), axis = (p1 - p0).normalized();
  const V3 b = n, d = axis.cross(b).normalized();
  const float len = (p1 - p0).norm();
  // Rings along the axis: the cylinder, then the rounded tip (a quarter circle of rings).
  std::vector<std::pair<float, float>> rings;  // (distance along the axis, radius)
  for (int k = 0; k <= 8; ++k) rings.push_back({len * k / 8, kFingerRadiusMm});
  for (int k = 1; k <= 6; ++k) {
    float a = 0.5f * float(M_PI) * k / 6;
    rings.push_back({len + kFingerRadiusMm * std::sin(a), kFingerRadiusMm * std::max(std::cos(a), 1e-3f)});
  }
  const int sides = 24;
  mesh::TriMesh m;
  for (const auto& [s, r] : rings)
    for (int i = 0; i < sides; ++i) {
      float a = 2.0f * float(M_PI) * i / sides;
      V3 radial = std::cos(a) * b + std::sin(a) * d;
      m.positions.push_back(p0 + s * axis + r * radial);
      V3 centre = p0 + std::min(s, len) * axis;
      m.normals.push_back((m.positions.back() - centre).normalized());
    }
  for (int k = 0; k + 1 < int(rings.size()); ++k)
    for (int i = 0; i < sides; ++i) {
      int a = k * sides + i, b2 = k * sides + (i + 1) % sides;
      m.triangles.emplace_back(a, b2, a + sides);
      m.triangles.emplace_back(b2, b2 + sides, a + sides);
    }
  m.materials.push_back(plain_material("finger", V3(0.56f, 0.34f, 0.25f), -1));
  m.triangle_material.assign(m.triangles.size(), 0);
  m.triangle_part.assign(m.triangles.size(), 0);
  m.part_names = {"finger"};
  return m;
}

}  // namespace lorgnette::synth
