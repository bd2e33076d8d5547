// Parametric frame construction: lens outlines per shape, swept rims/bridge/temples, lens slabs;
// see parametric.h. All geometry is built in canonical mm with g_c at the origin.
#include "mesh/parametric.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

#include "host/util/bounds.h"
#include "host/util/image_io.h"
#include "mesh/disney_brdf.h"

namespace lorgnette::mesh {
namespace {

using Section = std::array<Eigen::Vector3f, 4>;  // corners in order around the section

constexpr float kRimDepth = 4.0f;  // z thickness of rims and bridge
constexpr float kTempleW = 3.0f, kTempleH = 4.5f;
constexpr float kBendLength = 35.0f;  // temple length after the ear bend
constexpr float kBendAngle = 0.7f;    // radians the tip bends down
constexpr float kGroove = 0.6f;       // lens depth in the rim groove, as a fraction of the rim width

// Lens outline around its centre, counter-clockwise seen from the front; u = +1 is temporal.
std::vector<Eigen::Vector2f> lens_outline(FrameShape shape, float w, float h, int n, float temporal_sign) {
  std::vector<Eigen::Vector2f> out;
  float e = shape == FrameShape::kRect ? 5.0f : shape == FrameShape::kCateye ? 3.0f : 2.2f;
  for (int i = 0; i < n; ++i) {
    float th = 2.0f * kPi * i / n;
    float c = std::cos(th), s = std::sin(th);
    float x = 0.5f * w * std::copysign(std::pow(std::abs(c), 2.0f / e), c);
    float y = 0.5f * h * std::copysign(std::pow(std::abs(s), 2.0f / e), s);
    float u = x / (0.5f * w) * temporal_sign;  // -1 nasal .. +1 temporal
    if (shape == FrameShape::kAviator) y *= y > 0 ? 0.82f : 1.0f + 0.22f * std::max(0.0f, -u);
    if (shape == FrameShape::kCateye && y > 0)
      y += 0.3f * h * std::pow(std::max(0.0f, u), 2.0f) - 0.1f * h * std::max(0.0f, -u);
    out.emplace_back(x, y);
  }
  return out;
}

struct Builder {
  TriMesh& m;
  int add_vertex(const Eigen::Vector3f& p) {
    m.positions.push_back(p);
    return static_cast<int>(m.positions.size()) - 1;
  }
  void tri(int a, int b, int c, int part, int mat) {
    m.triangles.emplace_back(a, b, c);
    m.triangle_part.push_back(part);
    m.triangle_material.push_back(mat);
  }
  void quad(int a, int b, int c, int d, int part, int mat) {
    tri(a, b, c, part, mat), tri(a, c, d, part, mat);
  }
  // A closed surface swept through `sections` (a ring when `closed`, else capped at both ends).
  void sweep(const std::vector<Section>& sections, bool closed, int part, int mat) {
    std::vector<std::array<int, 4>> ids;
    for (const auto& s : sections)
      ids.push_back({add_vertex(s[0]), add_vertex(s[1]), add_vertex(s[2]), add_vertex(s[3])});
    size_t n = ids.size(), segs = closed ? n : n - 1;
    for (size_t i = 0; i < segs; ++i) {
      const auto& a = ids[i];
      const auto& b = ids[(i + 1) % n];
      for (int k = 0; k < 4; ++k) quad(a[k], a[(k + 1) % 4], b[(k + 1) % 4], b[k], part, mat);
    }
    if (!closed) {
      quad(ids[0][3], ids[0][2], ids[0][1], ids[0][0], part, mat);
      quad(ids[n - 1][0], ids[n - 1][1], ids[n - 1][2], ids[n - 1][3], part, mat);
    }
  }
  // A slab with outline `o` (star-shaped around `centre`) between z = z_back and z_front.
  void slab(const std::vector<Eigen::Vector3f>& front, const std::vector<Eigen::Vector3f>& back,
            const Eigen::Vector3f& cf, const Eigen::Vector3f& cb, int part, int mat) {
    int n = static_cast<int>(front.size());
    int c0 = add_vertex(cf), c1 = add_vertex(cb);
    std::vector<int> f, b;
    for (int i = 0; i < n; ++i) f.push_back(add_vertex(front[i])), b.push_back(add_vertex(back[i]));
    for (int i = 0; i < n; ++i) {
      int j = (i + 1) % n;
      tri(c0, f[i], f[j], part, mat);
      tri(c1, b[j], b[i], part, mat);
      quad(f[j], f[i], b[i], b[j], part, mat);
    }
  }
};

Material frame_material(const FrameParams& p) {
  Material m;
  m.name = "frame";
  m.base_color = p.color;
  m.metallic = p.metallic;
  m.roughness = p.roughness;
  return m;
}

Material lens_material(const FrameParams& p) {
  Material m;
  m.name = "lens";
  m.base_color = p.lens_tint;
  m.roughness = 0.02f;
  m.transmission = 1.0f;
  m.tint = p.lens_tint;
  m.ior = 1.5f;
  m.is_lens = true;
  return m;
}

}  // namespace

namespace {

// Outward 2D normals of a closed counter-clockwise outline.
std::vector<Eigen::Vector2f> outline_normals(const std::vector<Eigen::Vector2f>& o) {
  std::vector<Eigen::Vector2f> n;
  size_t k = o.size();
  for (size_t i = 0; i < k; ++i) {
    Eigen::Vector2f t = o[(i + 1) % k] - o[(i + k - 1) % k];
    n.push_back(Eigen::Vector2f(t.y(), -t.x()).normalized());
  }
  return n;
}

void add_lens_and_rim(Builder& b, const FrameParams& p, float h, float side, int rim_part, int lens_part) {
  const float xc = side * (0.5f * p.bridge + 0.5f * p.lens_width);
  // The lens (boxing size, as printed on frames) sits kGroove * rim deep in the rim's groove, so the
  // visible opening is that much smaller on every side.
  auto o =
      lens_outline(p.shape, p.lens_width - 2 * kGroove * p.rim, h - 2 * kGroove * p.rim, p.segments, side);
  auto n = outline_normals(o);
  const float zf = 0.5f * kRimDepth, zb = -0.5f * kRimDepth;
  std::vector<Section> ring;
  std::vector<Eigen::Vector3f> lf, lb;
  for (size_t i = 0; i < o.size(); ++i) {
    Eigen::Vector2f in = o[i], out = o[i] + p.rim * n[i], lens = o[i] + kGroove * p.rim * n[i];
    ring.push_back({Eigen::Vector3f(xc + in.x(), in.y(), zf), Eigen::Vector3f(xc + out.x(), out.y(), zf),
                    Eigen::Vector3f(xc + out.x(), out.y(), zb), Eigen::Vector3f(xc + in.x(), in.y(), zb)});
    lf.emplace_back(xc + lens.x(), lens.y(), 0.9f);
    lb.emplace_back(xc + lens.x(), lens.y(), -0.9f);
  }
  b.sweep(ring, true, rim_part, 0);
  b.slab(lf, lb, {xc, 0.0f, 0.9f}, {xc, 0.0f, -0.9f}, lens_part, 1);
}

// Returns the exact bridge underside point on x = 0 (g_c before the origin shift).
Eigen::Vector3f add_bridge(Builder& b, const FrameParams& p, float h, int part) {
  const float yb = 0.22f * h, arch = 1.5f, bh = std::max(2.5f, p.rim), xe = 0.5f * p.bridge + 0.5f * p.rim;
  const int segs = 16;  // even: x = 0 is a path vertex, where the section is exactly vertical
  std::vector<Section> path;
  for (int i = 0; i <= segs; ++i) {
    float x = -xe + 2.0f * xe * i / segs;
    float y = yb + arch * (1.0f - (x / xe) * (x / xe));
    float dy = -2.0f * arch * x / (xe * xe);
    Eigen::Vector3f c(x, y, 0), up = Eigen::Vector3f(-dy, 1.0f, 0.0f).normalized(), z(0, 0, 0.5f * kRimDepth);
    up *= 0.5f * bh;
    path.push_back({c + up + z, c - up + z, c - up - z, c + up - z});
  }
  b.sweep(path, false, part, 0);
  return {0.0f, yb + arch - 0.5f * bh, -0.5f * kRimDepth};
}

// Returns the exact ear point (temple underside at the start of the bend) of the temple on `side`.
Eigen::Vector3f add_temple(Builder& b, const FrameParams& p, float h, float side, int part) {
  const float xc = side * (0.5f * p.bridge + 0.5f * p.lens_width);
  auto o =
      lens_outline(p.shape, p.lens_width - 2 * kGroove * p.rim, h - 2 * kGroove * p.rim, p.segments, side);
  const float yh = 0.3f * h;
  Eigen::Vector2f edge = o[0];
  for (const auto& q : o)
    if (side * q.x() > 0 && std::abs(q.y() - yh) < std::abs(edge.y() - yh)) edge = q;
  const float xt = xc + edge.x() + side * (p.rim + 0.5f * kTempleW - 0.5f);
  const float z_hinge = -0.5f * kRimDepth, straight = p.temple_length - kBendLength;
  std::vector<Eigen::Vector3f> centre, tangent;
  centre.emplace_back(xt, yh, 0.5f * kRimDepth - 0.5f);
  tangent.emplace_back(0, 0, -1);
  Eigen::Vector3f knee(xt, yh, z_hinge - straight);
  centre.push_back(knee);
  tangent.emplace_back(0, 0, -1);
  const int bend_segs = 12;
  Eigen::Vector3f q = knee;
  for (int i = 1; i <= bend_segs; ++i) {
    float a0 = kBendAngle * (i - 0.5f) / bend_segs, a1 = kBendAngle * i / bend_segs;
    q += (kBendLength / bend_segs) * Eigen::Vector3f(0, -std::sin(a0), -std::cos(a0));
    centre.push_back(q);
    tangent.emplace_back(0, -std::sin(a1), -std::cos(a1));
  }
  std::vector<Section> path;
  const Eigen::Vector3f sx(0.5f * kTempleW, 0, 0);
  for (size_t i = 0; i < centre.size(); ++i) {
    Eigen::Vector3f up = Eigen::Vector3f::UnitX().cross(tangent[i]) * (0.5f * kTempleH);
    path.push_back({centre[i] + up - sx, centre[i] + up + sx, centre[i] - up + sx, centre[i] - up - sx});
  }
  b.sweep(path, false, part, 0);
  return {xt, yh - 0.5f * kTempleH, knee.z()};
}

float default_lens_height(const FrameParams& p) {
  switch (p.shape) {
    case FrameShape::kRound:
      return 0.9f * p.lens_width;
    case FrameShape::kRect:
      return 0.72f * p.lens_width;
    case FrameShape::kAviator:
      return 0.9f * p.lens_width;
    case FrameShape::kCateye:
      return 0.78f * p.lens_width;
  }
  return 0.8f * p.lens_width;
}

}  // namespace

FrameShape parse_frame_shape(const std::string& name) {
  if (name == "round") return FrameShape::kRound;
  if (name == "rect") return FrameShape::kRect;
  if (name == "aviator") return FrameShape::kAviator;
  if (name == "cateye") return FrameShape::kCateye;
  throw std::runtime_error(fmt::format("unknown frame shape '{}': use round, rect, aviator or cateye", name));
}

ParametricFrame make_parametric_frame(const FrameParams& p) {
  // The table's ranges (host/util/bounds.h), the same for `glasses make` and Glasses.make().
  check_bound(bounds::kLensWidth, p.lens_width);
  check_bound(bounds::kBridge, p.bridge);
  check_bound(bounds::kTempleLength, p.temple_length);
  check_bound(bounds::kRim, p.rim);
  check_bound_or_zero(bounds::kLensHeight, p.lens_height);
  check_bound(bounds::kMetallic, p.metallic);
  check_bound(bounds::kRoughness, p.roughness);
  if (p.segments < 16 || p.segments > 1024)
    throw std::runtime_error(fmt::format("outline segments {} outside 16..1024", p.segments));
  const float h = p.lens_height > 0 ? p.lens_height : default_lens_height(p);
  ParametricFrame f;
  TriMesh& m = f.mesh;
  m.materials = {frame_material(p), lens_material(p)};
  m.part_names = {"rim_left",     "rim_right", "bridge",    "temple_left",
                  "temple_right", "lens_left", "lens_right"};
  Builder b{m};
  add_lens_and_rim(b, p, h, +1.0f, 0, 5);
  add_lens_and_rim(b, p, h, -1.0f, 1, 6);
  Eigen::Vector3f gc = add_bridge(b, p, h, 2);
  Eigen::Vector3f gl = add_temple(b, p, h, +1.0f, 3);
  Eigen::Vector3f gr = add_temple(b, p, h, -1.0f, 4);
  for (auto& q : m.positions) q -= gc;
  m.units_to_mm = 1.0;
  f.ref.g_c = Eigen::Vector3f::Zero();
  f.ref.g_l = gl - gc;
  f.ref.g_r = gr - gc;
  f.ref.source = "parametric";
  return f;
}

Eigen::Vector3f parse_color(const std::string& text) {
  static const std::map<std::string, Eigen::Vector3f> names = {
      {"black", {0.02f, 0.02f, 0.025f}}, {"tortoise", {0.18f, 0.07f, 0.02f}}, {"gold", {0.85f, 0.55f, 0.2f}},
      {"silver", {0.7f, 0.7f, 0.72f}},   {"red", {0.5f, 0.03f, 0.03f}},       {"blue", {0.03f, 0.08f, 0.4f}},
      {"clear", {0.9f, 0.92f, 0.93f}},   {"grey", {0.3f, 0.3f, 0.3f}},        {"green", {0.15f, 0.3f, 0.15f}},
      {"brown", {0.35f, 0.2f, 0.1f}}};
  if (auto it = names.find(text); it != names.end()) return it->second;
  if (text.size() == 7 && text[0] == '#') {
    Eigen::Vector3f c;
    for (int k = 0; k < 3; ++k) {
      const std::string hex = text.substr(1 + 2 * k, 2);
      if (!std::isxdigit(static_cast<unsigned char>(hex[0])) ||
          !std::isxdigit(static_cast<unsigned char>(hex[1])))
        throw std::runtime_error(fmt::format("colour '{}' is not #rrggbb (hex digits)", text));
      int v = std::stoi(hex, nullptr, 16);
      c[k] = srgb_to_linear(v / 255.0f);
    }
    return c;
  }
  float r, g, bl;
  char extra;
  if (std::sscanf(text.c_str(), "%f,%f,%f%c", &r, &g, &bl, &extra) == 3 && r >= 0 && g >= 0 && bl >= 0 &&
      r <= 1 && g <= 1 && bl <= 1)
    return {r, g, bl};
  throw std::runtime_error(
      fmt::format("colour '{}' not understood: use #rrggbb, r,g,b in 0..1, or a name "
                  "(black, tortoise, gold, silver, red, blue, clear, grey, green, brown)",
                  text));
}

}  // namespace lorgnette::mesh
