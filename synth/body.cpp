// Neck and shoulders; see body.h. The loft is a grid over (angle, height): each ring is a
// superellipse |x/a|^n + |z/b|^n = 1 around the centre (0, y, zc(y)), closed with flat caps.
#include "synth/body.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace lorgnette::synth {
namespace {

using V3 = Eigen::Vector3f;

float smoothstep(float e0, float e1, float x) {
  float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

struct Ring {
  float a, b, zc, n;  // half-width (x), half-depth (z), centre z, superellipse exponent
};

// Profile against y (mm). Neck radius slightly above the head's neck cylinder (0.34 * width) so the
// loft encloses the head's flat neck cut; shoulders widen over ~70 mm below the neck base.
Ring ring_at(const HeadParams& p, float y) {
  const float neck_r = 0.34f * p.head_width + 1.5f;
  const float base = -p.face_length - 70.0f;                     // where the trapezius starts
  const float shoulder = base - 60.0f;                           // shoulder line
  const float s = 1.0f - smoothstep(shoulder, base + 10.0f, y);  // 0 at the neck, 1 at the shoulder line
  Ring r;
  r.a = neck_r + s * (1.45f * p.head_width - neck_r);
  r.b = neck_r + s * (0.58f * p.head_depth - neck_r);
  r.zc = -12.0f - 10.0f * s;
  r.n = 2.0f + 1.2f * s;  // round neck, boxier chest
  return r;
}

V3 ring_point(const Ring& r, float y, float angle) {
  float c = std::cos(angle), s = std::sin(angle);
  float e = 2.0f / r.n;
  float x = r.a * std::copysign(std::pow(std::abs(s), e), s);
  float z = r.b * std::copysign(std::pow(std::abs(c), e), c);
  return {x, y, r.zc + z};
}

// Skin above the collar, a striped shirt with a little weave below (linear RGB).
Image body_texture(const HeadParams& p, float top, float bottom, float collar) {
  const int w = 512, h = 256;
  Image img(w, h, 3);
  const V3 shirt(0.16f, 0.22f, 0.38f), stripe(0.55f, 0.55f, 0.52f);
  for (int j = 0; j < h; ++j) {
    float y = top + (bottom - top) * (j + 0.5f) / h;
    for (int i = 0; i < w; ++i) {
      float u = (i + 0.5f) / w;
      V3 c;
      // Collar line dips in front (u = 0.5 faces +z).
      float dip = 25.0f * std::pow(std::max(0.0f, std::cos(float(M_PI) * 2.0f * (u - 0.5f))), 4.0f);
      if (y > collar - dip) {
        c = p.skin * (0.985f + 0.015f * std::sin(0.37f * j));
      } else {
        bool on_stripe = std::fmod(u * 48.0f, 1.0f) < 0.25f;
        c = on_stripe ? stripe : shirt;
        c *= 0.9f + 0.1f * std::sin(1.7f * i) * std::sin(1.3f * j);
      }
      for (int k = 0; k < 3; ++k) img.at(i, j, k) = c[k];
    }
  }
  return img;
}

}  // namespace

float body_bottom_mm(const HeadParams& p) { return -p.face_length - 420.0f; }

mesh::TriMesh make_neck_and_shoulders(const HeadParams& p) {
  const float top = -p.face_length - 20.0f;  // inside the head's neck
  const float bottom = body_bottom_mm(p);
  const float collar = -p.face_length - 85.0f;
  const int cols = 256, rows = 160;
  mesh::TriMesh m;
  for (int j = 0; j <= rows; ++j) {
    float y = top + (bottom - top) * float(j) / rows;
    Ring r = ring_at(p, y);
    for (int i = 0; i <= cols; ++i) {
      float angle = 2.0f * float(M_PI) * float(i) / cols;  // 0 = front (+z), towards +x first
      m.positions.push_back(ring_point(r, y, angle));
      m.uvs.emplace_back(0.5f + float(i) / cols, float(j) / rows);  // u = 0.5 at the front after wrap
    }
  }
  auto idx = [&](int i, int j) { return j * (cols + 1) + i; };
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) {
      // Outward normals: the angle turns from +z towards +x, y decreases with j.
      m.triangles.emplace_back(idx(i, j), idx(i, j + 1), idx(i + 1, j));
      m.triangles.emplace_back(idx(i + 1, j), idx(i, j + 1), idx(i + 1, j + 1));
    }
  // Flat caps (the top one hides inside the head).
  for (int cap = 0; cap < 2; ++cap) {
    int j = cap == 0 ? 0 : rows;
    float y = top + (bottom - top) * float(j) / rows;
    int centre = int(m.positions.size());
    m.positions.emplace_back(0.0f, y, ring_at(p, y).zc);
    m.uvs.emplace_back(0.5f, cap == 0 ? 0.0f : 1.0f);
    for (int i = 0; i < cols; ++i) {
      if (cap == 0)
        m.triangles.emplace_back(centre, idx(i, j), idx(i + 1, j));
      else
        m.triangles.emplace_back(centre, idx(i + 1, j), idx(i, j));
    }
  }
  m.normals.assign(m.positions.size(), V3::Zero());
  for (const auto& t : m.triangles) {
    V3 n = (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]);
    for (int k = 0; k < 3; ++k) m.normals[t[k]] += n;
  }
  for (int j = 0; j <= rows; ++j) {  // weld the seam
    V3 s = m.normals[idx(0, j)] + m.normals[idx(cols, j)];
    m.normals[idx(0, j)] = m.normals[idx(cols, j)] = s;
  }
  for (auto& n : m.normals) n = n.norm() > 0 ? n.normalized() : V3(0, 1, 0);
  m.textures.push_back(body_texture(p, top, bottom, collar));
  mesh::Material mat;
  mat.name = "procedural_body";
  mat.base_color = V3(1, 1, 1);
  mat.base_color_texture = 0;
  m.materials.push_back(mat);
  m.triangle_material.assign(m.triangles.size(), 0);
  m.triangle_part.assign(m.triangles.size(), 0);
  m.part_names = {"body"};
  m.units_to_mm = 1.0;
  return m;
}

}  // namespace lorgnette::synth
