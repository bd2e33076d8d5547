// Building the procedural head; see procedural_head.h. The surface is sampled on a latitude-longitude
// grid of rays from the head centre (the shape is star-shaped), which gives a watertight mesh whose
// texture coordinates are the grid coordinates; the painted texture is baked on that grid and the
// landmarks are found by ray casting the finished mesh with Embree.
#include "synth/procedural_head.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "mesh/embree_scene.h"
#include "synth/head_paint.h"
#include "synth/head_shape.h"

namespace lorgnette::synth {
namespace {

using V3 = Eigen::Vector3f;

V3 grid_direction(float u, float v) {
  // u = 0.5 faces forward (+z); the seam (u = 0 / 1) is at the back of the head; v = 0 is the crown.
  float phi = float(M_PI) * (2.0f * u - 1.0f), theta = float(M_PI) * v;
  return {std::sin(theta) * std::sin(phi), std::cos(theta), std::sin(theta) * std::cos(phi)};
}

struct Grid {
  int cols, rows;  // vertices: (cols + 1) x (rows + 1)
  std::vector<V3> pos;
  const V3& at(int i, int j) const { return pos[size_t(j) * (cols + 1) + i]; }
  // Bilinear surface point at texture coordinates (u, v).
  V3 sample(float u, float v) const {
    float x = std::clamp(u, 0.0f, 1.0f) * cols, y = std::clamp(v, 0.0f, 1.0f) * rows;
    int i = std::min(int(x), cols - 1), j = std::min(int(y), rows - 1);
    float fx = x - i, fy = y - j;
    return (1 - fy) * ((1 - fx) * at(i, j) + fx * at(i + 1, j)) +
           fy * ((1 - fx) * at(i, j + 1) + fx * at(i + 1, j + 1));
  }
};

Grid sample_surface(const HeadShape& shape, int cols, int rows) {
  Grid g{cols, rows, std::vector<V3>(size_t(cols + 1) * (rows + 1))};
  mesh::parallel_rows(rows + 1, 0, [&](int j) {
    for (int i = 0; i <= cols; ++i) {
      if (i == cols) continue;  // the seam column duplicates column 0 (filled below)
      V3 d = grid_direction(float(i) / cols, float(j) / rows);
      g.pos[size_t(j) * (cols + 1) + i] = shape.surface_radius(d) * d;
    }
    g.pos[size_t(j) * (cols + 1) + cols] = g.pos[size_t(j) * (cols + 1)];
  });
  return g;
}

mesh::TriMesh grid_mesh(const Grid& g) {
  mesh::TriMesh m;
  m.positions = g.pos;
  m.uvs.reserve(g.pos.size());
  for (int j = 0; j <= g.rows; ++j)
    for (int i = 0; i <= g.cols; ++i) m.uvs.emplace_back(float(i) / g.cols, float(j) / g.rows);
  auto idx = [&](int i, int j) { return j * (g.cols + 1) + i; };
  for (int j = 0; j < g.rows; ++j)
    for (int i = 0; i < g.cols; ++i) {
      // Counter-clockwise seen from outside (normals point out of the head).
      if (j > 0) m.triangles.emplace_back(idx(i, j), idx(i, j + 1), idx(i + 1, j));
      if (j < g.rows - 1) m.triangles.emplace_back(idx(i + 1, j), idx(i, j + 1), idx(i + 1, j + 1));
    }
  // Area-weighted vertex normals; the seam and the poles share positions, so weld them by position.
  m.normals.assign(m.positions.size(), V3::Zero());
  for (const auto& t : m.triangles) {
    V3 n = (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]);
    for (int k = 0; k < 3; ++k) m.normals[t[k]] += n;
  }
  for (int j = 0; j <= g.rows; ++j) {
    V3 s = m.normals[idx(0, j)] + m.normals[idx(g.cols, j)];
    m.normals[idx(0, j)] = m.normals[idx(g.cols, j)] = s;
  }
  for (int pole : {0, g.rows}) {
    V3 s = V3::Zero();
    for (int i = 0; i <= g.cols; ++i) s += m.normals[idx(i, pole)];
    for (int i = 0; i <= g.cols; ++i) m.normals[idx(i, pole)] = s;
  }
  for (auto& n : m.normals) n = n.norm() > 0 ? n.normalized() : V3(0, 1, 0);
  m.triangle_material.assign(m.triangles.size(), 0);
  m.triangle_part.assign(m.triangles.size(), 0);
  m.part_names = {"head"};
  m.units_to_mm = 1.0;
  return m;
}

V3 cast(const mesh::EmbreeScene& scene, const V3& origin, const V3& dir, const char* what) {
  mesh::Hit h = scene.intersect(origin, dir.normalized());
  if (!h.hit) throw std::runtime_error(fmt::format("procedural head: landmark '{}' missed the mesh", what));
  return h.position;
}

// Frontal contour point for jaw landmark (x, y): the outermost surface vertex along the frontal-plane
// ray from the face centre through (x, y), in front of `min_z` (excludes ears and neck).
V3 contour_point(const mesh::TriMesh& m, const Eigen::Vector2f& target, float min_z) {
  Eigen::Vector2f c(0.0f, -45.0f), dir = (target - c).normalized();
  float best = -1.0f;
  V3 best_p = V3::Zero();
  for (const V3& p : m.positions) {
    if (p.z() < min_z) continue;
    Eigen::Vector2f q = p.head<2>() - c;
    float along = q.dot(dir), across = std::abs(q.x() * dir.y() - q.y() * dir.x());
    if (across < 1.5f && along > best) best = along, best_p = p;
  }
  return best_p;
}

void find_landmarks(ProceduralHead& head, const HeadShape& shape) {
  mesh::EmbreeScene scene(head.mesh);
  const V3 back(0, 0, -1);
  for (int i = 17; i < 68; ++i) {
    const auto& q = head.layout.ibug[i];
    head.ibug[i] = cast(scene, V3(q.x(), q.y(), 400.0f), back, "ibug");
  }
  for (int i = 0; i < 17; ++i) {
    int k = std::min(i, 16 - i);
    float min_z = k <= 3 ? shape.ear_centre(1).z() + 25.0f : (k == 4 ? 35.0f : 50.0f);
    head.ibug[i] = contour_point(head.mesh, head.layout.ibug[i], min_z);
  }
  auto& L = head.landmarks;
  L["nose_bridge"] = head.ibug[27];
  L["nose_tip"] = head.ibug[30];
  L["chin"] = head.ibug[8];
  L["eye_r_outer"] = head.ibug[36], L["eye_r_inner"] = head.ibug[39];
  L["eye_l_inner"] = head.ibug[42], L["eye_l_outer"] = head.ibug[45];
  for (int s = -1; s <= 1; s += 2) {
    const EyeShape& eye = s < 0 ? head.layout.eye_r : head.layout.eye_l;
    const char* side = s < 0 ? "r" : "l";
    L[fmt::format("pupil_{}", side)] =
        cast(scene, V3(eye.centre().x(), eye.centre().y(), 400.0f), back, "pupil");
    V3 ec = shape.ear_centre(s);
    // Ear top: a downward ray through the outer half of the ear ellipsoid's top.
    L[fmt::format("ear_top_{}", side)] =
        cast(scene, V3(ec.x() + s * 3.0f, 300.0f, ec.z()), V3(0, -1, 0), "ear_top");
    // Ear rest (where a temple arm lies): the lowest point of the crease between the skull and the
    // ear's top, on the profile of downward rays across the ear root, a little in front of its centre.
    // |x| in the bound: ec.x() is negative on the wearer's right, where a signed bound ran no ray and
    // left the right ear's rest at its top.
    V3 rest = L[fmt::format("ear_top_{}", side)];
    const float z = ec.z() + 0.3f * shape.ear_radii().z(), skull = 0.5f * head.params.head_width;
    for (float x = skull - 4.0f; x <= std::abs(ec.x()) + 3.0f; x += 0.25f) {
      mesh::Hit h = scene.intersect(V3(s * x, 300.0f, z), V3(0, -1, 0));
      if (h.hit && h.position.y() < rest.y()) rest = h.position;
    }
    L[fmt::format("ear_rest_{}", side)] = rest;
    const V3& corner = L[s < 0 ? "eye_r_outer" : "eye_l_outer"];
    const float temple_z = corner.z() - kTempleDepthShare * (corner.z() - rest.z());
    (s < 0 ? head.temple_r : head.temple_l) =
        cast(scene, V3(s * 400.0f, corner.y(), temple_z), V3(-s, 0, 0), "temple");
  }
}

}  // namespace

ProceduralHead make_procedural_head(const HeadParams& params, const HeadMeshOptions& options) {
  validate(params);
  if (options.longitudes < 64 || options.latitudes < 32 || options.texture_width < 256)
    throw std::runtime_error(
        fmt::format("procedural head: mesh grid {}x{} / texture {} too coarse (need >= 64x32 and 256)",
                    options.longitudes, options.latitudes, options.texture_width));
  ProceduralHead head;
  head.params = params;
  head.layout = make_face_layout(params);
  HeadShape shape(params, head.layout);
  Grid grid = sample_surface(shape, options.longitudes, options.latitudes);
  head.mesh = grid_mesh(grid);
  HeadPainter painter(params, head.layout, shape.ear_centre(1), shape.ear_radii(),
                      shape.eye_corner_z() - 50.0f);
  head.mesh.textures.push_back(bake_latlong_texture(painter, options.texture_width,
                                                    [&](float u, float v) { return grid.sample(u, v); }));
  mesh::Material skin;
  skin.name = "procedural_skin";
  skin.base_color = V3(1, 1, 1);
  skin.roughness = 0.6f;
  skin.base_color_texture = 0;
  head.mesh.materials.push_back(skin);
  find_landmarks(head, shape);
  return head;
}

}  // namespace lorgnette::synth
