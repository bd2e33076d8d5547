// Rooms for synthetic captures; see room.h. Every surface is a textured quad with its own four
// vertices (flat normals), texture coordinates in metres times a tiling rate so texel density is
// the same everywhere. Textures are small procedural images (wallpaper, planks, books, fabric,
// pictures) with value noise, so the background has the kind of detail a NeRF latches onto.
#include "synth/room.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace lorgnette::synth {
namespace {

using V3 = Eigen::Vector3f;

float hash01(uint32_t a, uint32_t b, uint32_t c) {
  uint32_t h = a * 73856093u ^ b * 19349663u ^ c * 83492791u;
  h ^= h >> 13;
  h *= 0x5bd1e995u;
  h ^= h >> 15;
  return float(h & 0xffffffu) / float(0x1000000);
}

// Smooth value noise in [0, 1) with period `cells` (tileable).
float value_noise(float x, float y, int cells, uint32_t seed) {
  int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  float fx = x - x0, fy = y - y0;
  fx = fx * fx * (3 - 2 * fx), fy = fy * fy * (3 - 2 * fy);
  auto h = [&](int i, int j) {
    return hash01(uint32_t(((i % cells) + cells) % cells), uint32_t(((j % cells) + cells) % cells), seed);
  };
  return (1 - fy) * ((1 - fx) * h(x0, y0) + fx * h(x0 + 1, y0)) +
         fy * ((1 - fx) * h(x0, y0 + 1) + fx * h(x0 + 1, y0 + 1));
}

enum class Pattern { Wallpaper, Planks, Books, Fabric, Picture, Paint, Tiles, Plain };

Image make_texture(Pattern pat, const V3& base, const V3& accent, uint32_t seed) {
  const int n = 256;
  Image img(n, n, 3);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      float u = (i + 0.5f) / n, v = (j + 0.5f) / n;
      float noise =
          0.5f * value_noise(u * 16, v * 16, 16, seed) + 0.5f * value_noise(u * 64, v * 64, 64, seed + 1);
      V3 c = base;
      switch (pat) {
        case Pattern::Wallpaper: {
          float stripe = std::fmod(u * 8.0f, 1.0f);
          float motif = std::sin(float(M_PI) * 16.0f * v + 6.0f * std::sin(float(M_PI) * 8.0f * u));
          c = stripe < 0.12f ? accent : base;
          if (stripe > 0.4f && stripe < 0.6f && motif > 0.6f) c = 0.5f * (base + accent);
          c *= 0.9f + 0.2f * noise;
          break;
        }
        case Pattern::Planks: {
          int plank = int(v * 6.0f);
          float shift = hash01(uint32_t(plank), 7u, seed);
          float grain = value_noise(u * 4.0f + shift * 10.0f, v * 96.0f, 96, seed + 2);
          c = base * (0.75f + 0.3f * hash01(uint32_t(plank), 3u, seed)) * (0.85f + 0.3f * grain);
          if (std::fmod(v * 6.0f, 1.0f) < 0.04f || std::fmod(u * 2.0f + shift, 1.0f) < 0.01f) c *= 0.45f;
          break;
        }
        case Pattern::Books: {
          int shelf = int(v * 4.0f);
          float sv = std::fmod(v * 4.0f, 1.0f);
          int book = int(u * 28.0f + 3.0f * hash01(uint32_t(shelf), 1u, seed));
          V3 spine(hash01(uint32_t(book), uint32_t(shelf), seed),
                   hash01(uint32_t(book), uint32_t(shelf), seed + 5),
                   hash01(uint32_t(book), uint32_t(shelf), seed + 9));
          float height = 0.55f + 0.35f * hash01(uint32_t(book), uint32_t(shelf), seed + 11);
          c = sv < 0.08f ? accent
                         : (sv > 1.0f - height ? V3(V3::Constant(0.05f) + 0.6f * spine.cwiseProduct(spine))
                                               : V3(0.3f * accent));
          c *= 0.9f + 0.2f * noise;
          break;
        }
        case Pattern::Fabric: {
          float weave = 0.5f + 0.5f * std::sin(float(M_PI) * 128.0f * u) * std::sin(float(M_PI) * 128.0f * v);
          c = base * (0.8f + 0.25f * noise + 0.1f * weave);
          if (std::fmod(u * 4.0f + v * 4.0f, 1.0f) < 0.05f) c = 0.6f * c + 0.4f * accent;
          break;
        }
        case Pattern::Picture: {
          float a = value_noise(u * 4, v * 4, 4, seed + 3), b = value_noise(u * 8, v * 8, 8, seed + 4);
          c = (a * base + (1 - a) * accent) * (0.7f + 0.6f * b);
          if (u < 0.06f || u > 0.94f || v < 0.06f || v > 0.94f) c = V3(0.08f, 0.06f, 0.04f);
          break;
        }
        case Pattern::Paint:
          c = base * (0.88f + 0.24f * noise);
          break;
        case Pattern::Plain:
          c = base;
          break;
        case Pattern::Tiles: {
          float tu = std::fmod(u * 4.0f, 1.0f), tv = std::fmod(v * 4.0f, 1.0f);
          c = (tu < 0.04f || tv < 0.04f) ? accent : base * (0.9f + 0.2f * noise);
          break;
        }
      }
      for (int k = 0; k < 3; ++k) img.at(i, j, k) = std::clamp(c[k], 0.0f, 1.0f);
    }
  return img;
}

struct RoomBuilder {
  mesh::TriMesh m;

  int material(Pattern pat, const V3& base, const V3& accent, uint32_t seed) {
    m.textures.push_back(make_texture(pat, base, accent, seed));
    mesh::Material mat;
    mat.name = fmt::format("room_{}", m.materials.size());
    mat.base_color = V3(1, 1, 1);
    mat.roughness = 0.8f;
    mat.base_color_texture = int(m.textures.size()) - 1;
    m.materials.push_back(mat);
    return int(m.materials.size()) - 1;
  }

  // Quad p0 p1 p2 p3 (counter-clockwise seen from the side the normal points to); the texture
  // repeats every `tile` millimetres (0: stretched once over the quad).
  void quad(const V3& p0, const V3& p1, const V3& p2, const V3& p3, int mat, float tile) {
    int base = int(m.positions.size());
    V3 n = (p1 - p0).cross(p3 - p0).normalized();
    float su = tile > 0 ? (p1 - p0).norm() / tile : 1.0f, sv = tile > 0 ? (p3 - p0).norm() / tile : 1.0f;
    const V3 ps[4] = {p0, p1, p2, p3};
    const Eigen::Vector2f uv[4] = {{0, sv}, {su, sv}, {su, 0}, {0, 0}};
    for (int k = 0; k < 4; ++k) {
      m.positions.push_back(ps[k]);
      m.normals.push_back(n);
      m.uvs.push_back(uv[k]);
    }
    m.triangles.emplace_back(base, base + 1, base + 2);
    m.triangles.emplace_back(base, base + 2, base + 3);
    m.triangle_material.push_back(mat);
    m.triangle_material.push_back(mat);
  }

  // Axis-aligned box with outward faces; `front_mat` on the +z face (shelves, pictures, screens).
  void box(const V3& lo, const V3& hi, int mat, int front_mat, float tile) {
    V3 c[8];
    for (int k = 0; k < 8; ++k)
      c[k] = V3(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
    quad(c[4], c[5], c[7], c[6], front_mat, front_mat == mat ? tile : 0.0f);  // +z
    quad(c[1], c[0], c[2], c[3], mat, tile);                                  // -z
    quad(c[5], c[1], c[3], c[7], mat, tile);                                  // +x
    quad(c[0], c[4], c[6], c[2], mat, tile);                                  // -x
    quad(c[6], c[7], c[3], c[2], mat, tile);                                  // +y
    quad(c[0], c[1], c[5], c[4], mat, tile);                                  // -y
  }

  // Floor at y, walls at x = xl / xr and z = zb, open towards +z and above y_top.
  void shell(float y, float xl, float xr, float zb, float zf, float y_top, int floor_mat, int wall_mat,
             int side_mat) {
    quad(V3(xl, y, zf), V3(xr, y, zf), V3(xr, y, zb), V3(xl, y, zb), floor_mat, 600.0f);
    quad(V3(xl, y, zb), V3(xr, y, zb), V3(xr, y_top, zb), V3(xl, y_top, zb), wall_mat, 900.0f);
    quad(V3(xl, y, zf), V3(xl, y, zb), V3(xl, y_top, zb), V3(xl, y_top, zf), side_mat, 900.0f);
    quad(V3(xr, y, zb), V3(xr, y, zf), V3(xr, y_top, zf), V3(xr, y_top, zb), side_mat, 900.0f);
  }
};

// Layout 1, a living room: wallpaper 1.6 m behind, a bookshelf 1.2 m behind to the right (the
// subject's right is -x), a picture, an armchair 0.6 m behind to the left, a door on the right wall.
void living_room(RoomBuilder& b) {
  int floor = b.material(Pattern::Planks, V3(0.42f, 0.25f, 0.12f), V3(0, 0, 0), 11);
  int wall = b.material(Pattern::Wallpaper, V3(0.55f, 0.52f, 0.40f), V3(0.30f, 0.36f, 0.28f), 12);
  int side = b.material(Pattern::Paint, V3(0.50f, 0.46f, 0.42f), V3(0, 0, 0), 13);
  int books = b.material(Pattern::Books, V3(0, 0, 0), V3(0.30f, 0.20f, 0.10f), 14);
  int wood = b.material(Pattern::Planks, V3(0.30f, 0.18f, 0.09f), V3(0, 0, 0), 15);
  int picture = b.material(Pattern::Picture, V3(0.70f, 0.30f, 0.10f), V3(0.10f, 0.25f, 0.55f), 16);
  int fabric = b.material(Pattern::Fabric, V3(0.45f, 0.08f, 0.07f), V3(0.80f, 0.70f, 0.40f), 17);
  const float y0 = -1500.0f;
  b.shell(y0, -2400.0f, 2200.0f, -1600.0f, 1400.0f, 1300.0f, floor, wall, side);
  b.box(V3(-1500, y0, -1600), V3(-600, 350, -1250), wood, books, 500.0f);     // bookshelf
  b.box(V3(-100, -150, -1600), V3(700, 400, -1570), wood, picture, 500.0f);   // picture
  b.box(V3(350, y0, -1000), V3(1100, -650, -450), fabric, fabric, 400.0f);    // armchair seat
  b.box(V3(350, -650, -1000), V3(1100, -150, -850), fabric, fabric, 400.0f);  // armchair back
  b.box(V3(-2400, y0, -300), V3(-2370, 550, 600), wood, wood, 500.0f);        // door
  b.box(V3(1500, y0, -1500), V3(1900, -700, -1100), side, wood, 400.0f);      // side table
}

// Layout 2, a corner office: a desk 0.4 m behind to the right with a monitor, a near side wall
// 1 m to the left, tiles and a cabinet 2.8 m behind, a window-like bright panel.
void office(RoomBuilder& b) {
  int floor = b.material(Pattern::Tiles, V3(0.35f, 0.36f, 0.38f), V3(0.15f, 0.15f, 0.16f), 21);
  int wall = b.material(Pattern::Paint, V3(0.30f, 0.42f, 0.50f), V3(0, 0, 0), 22);
  int side = b.material(Pattern::Wallpaper, V3(0.62f, 0.60f, 0.55f), V3(0.50f, 0.28f, 0.20f), 23);
  int desk = b.material(Pattern::Planks, V3(0.55f, 0.42f, 0.28f), V3(0, 0, 0), 24);
  int screen = b.material(Pattern::Picture, V3(0.10f, 0.30f, 0.60f), V3(0.80f, 0.80f, 0.85f), 25);
  int metal = b.material(Pattern::Paint, V3(0.20f, 0.20f, 0.22f), V3(0, 0, 0), 26);
  int window = b.material(Pattern::Tiles, V3(0.85f, 0.88f, 0.90f), V3(0.25f, 0.25f, 0.25f), 27);
  int books = b.material(Pattern::Books, V3(0, 0, 0), V3(0.25f, 0.25f, 0.28f), 28);
  const float y0 = -1300.0f;
  b.shell(y0, -2800.0f, 1000.0f, -2800.0f, 1300.0f, 1400.0f, floor, wall, side);
  b.box(V3(-1400, -550, -1100), V3(-400, -510, -400), desk, desk, 500.0f);   // desk top
  b.box(V3(-1380, y0, -1080), V3(-1330, -550, -420), metal, metal, 400.0f);  // desk legs
  b.box(V3(-470, y0, -1080), V3(-420, -550, -420), metal, metal, 400.0f);
  b.box(V3(-1150, -510, -1000), V3(-600, -150, -960), metal, screen, 400.0f);  // monitor
  b.box(V3(200, y0, -2800), V3(900, 300, -2350), metal, books, 500.0f);        // cabinet
  b.box(V3(-2200, -300, -2800), V3(-900, 900, -2780), metal, window, 400.0f);  // window
  b.box(V3(500, y0, -900), V3(800, -900, -600), desk, desk, 300.0f);           // crate beside
}

// Layout 3, a plain room: one wall `wall_mm` behind, floor and side walls of the same paint, no
// texture and no furniture (room.h); with a window, its pane just in front of the wall, black
// (it reflects nothing the daylight does not drown) and glowing.
void plain_room(RoomBuilder& b, const RoomPlacement& p) {
  if (!(p.wall_mm >= 200.0f && p.wall_mm <= 5000.0f))
    throw std::runtime_error(
        fmt::format("plain room: the wall must lie 200-5000 mm behind, not {}", p.wall_mm));
  const int paint = b.material(Pattern::Plain, p.wall_rgb, V3(0, 0, 0), 31);
  b.shell(-1400.0f, -2500.0f, 2500.0f, -p.wall_mm, 1500.0f, 1400.0f, paint, paint, paint);
  if (!p.window) return;
  const int pane = b.material(Pattern::Plain, V3(0, 0, 0), V3(0, 0, 0), 32);
  b.m.materials[size_t(pane)].emission = window_daylight();
  const WindowRect& w = kWindowMm;
  const float z = -p.wall_mm + kWindowPaneMm;
  b.quad(V3(w.x0, w.y0, z), V3(w.x1, w.y0, z), V3(w.x1, w.y1, z), V3(w.x0, w.y1, z), pane, 0.0f);
}

// Solid angle (sr) of the rectangle [x0, x1] x [y0, y1] in a plane at distance d, seen from the foot
// of the perpendicular at the origin: inclusion-exclusion over the corner rectangles' exact formula.
float rectangle_solid_angle(const WindowRect& r, float d) {
  auto corner = [d](float x, float y) { return std::atan(x * y / (d * std::sqrt(x * x + y * y + d * d))); };
  return corner(r.x1, r.y1) - corner(r.x0, r.y1) - corner(r.x1, r.y0) + corner(r.x0, r.y0);
}

}  // namespace

StudioLighting room_lighting(const RoomPlacement& plain, const StudioLighting& front) {
  if (!plain.window) return front;
  const WindowRect& w = kWindowMm;
  const float d = plain.wall_mm - kWindowPaneMm;
  const V3 daylight = window_daylight();
  const float luminance = 0.2126f * daylight.x() + 0.7152f * daylight.y() + 0.0722f * daylight.z();
  StudioLighting l = front;
  l.key_dir = V3(0.5f * (w.x0 + w.x1), 0.5f * (w.y0 + w.y1), -d).normalized();
  const float nearest_edge = std::min({-w.x0, w.x1, -w.y0, w.y1});
  l.key_radius_deg = std::atan(nearest_edge / d) * 180.0f / float(M_PI);
  l.key = luminance * rectangle_solid_angle(w, d) / float(M_PI);
  l.fill = front.fill / 3.0f;
  return l;
}

mesh::TriMesh make_room(const RoomPlacement& placement) {
  RoomBuilder b;
  switch (placement.layout) {
    case 1:
      living_room(b);
      break;
    case 2:
      office(b);
      break;
    case kPlainRoomLayout:
      plain_room(b, placement);
      break;
    default:
      throw std::runtime_error(
          fmt::format("room layout {} does not exist: use 1..{}", placement.layout, kRoomLayouts));
  }
  b.m.triangle_part.assign(b.m.triangles.size(), 0);
  b.m.part_names = {"room"};
  b.m.units_to_mm = 1.0;
  mesh::TriMesh out;
  append_mesh(out, b.m, placement.mm_to_dataset);
  return out;
}

void append_mesh(mesh::TriMesh& dst, const mesh::TriMesh& src, const Eigen::Matrix4f& transform) {
  const int v0 = int(dst.positions.size()), m0 = int(dst.materials.size()), t0 = int(dst.textures.size());
  const int p0 = int(dst.part_names.size());
  const Eigen::Matrix3f lin = transform.topLeftCorner<3, 3>();
  const Eigen::Matrix3f nmat = lin.inverse().transpose();
  for (const V3& p : src.positions) dst.positions.push_back(lin * p + transform.topRightCorner<3, 1>());
  std::vector<V3> normals = src.normals;
  if (normals.size() != src.positions.size()) {  // none given: area-weighted vertex normals
    normals.assign(src.positions.size(), V3::Zero());
    for (const auto& t : src.triangles) {
      V3 n = (src.positions[t[1]] - src.positions[t[0]]).cross(src.positions[t[2]] - src.positions[t[0]]);
      for (int k = 0; k < 3; ++k) normals[t[k]] += n;
    }
  }
  if (dst.normals.size() != size_t(v0)) dst.normals.resize(v0, V3(0, 1, 0));
  for (const V3& n : normals) {
    V3 t = nmat * n;
    dst.normals.push_back(t.norm() > 0 ? V3(t.normalized()) : V3(0, 1, 0));
  }
  if (dst.uvs.size() != size_t(v0)) dst.uvs.resize(v0, Eigen::Vector2f::Zero());
  if (src.uvs.size() == src.positions.size())
    dst.uvs.insert(dst.uvs.end(), src.uvs.begin(), src.uvs.end());
  else
    dst.uvs.resize(dst.positions.size(), Eigen::Vector2f::Zero());
  for (const auto& t : src.triangles) dst.triangles.emplace_back(t + Eigen::Vector3i::Constant(v0));
  for (size_t i = 0; i < src.triangles.size(); ++i) {
    dst.triangle_material.push_back(i < src.triangle_material.size() ? src.triangle_material[i] + m0 : m0);
    dst.triangle_part.push_back(i < src.triangle_part.size() ? src.triangle_part[i] + p0 : p0);
  }
  for (mesh::Material mat : src.materials) {
    if (mat.base_color_texture >= 0) mat.base_color_texture += t0;
    dst.materials.push_back(mat);
  }
  if (src.materials.empty()) dst.materials.push_back(mesh::Material{});
  dst.textures.insert(dst.textures.end(), src.textures.begin(), src.textures.end());
  dst.part_names.insert(dst.part_names.end(), src.part_names.begin(), src.part_names.end());
  if (src.part_names.empty()) dst.part_names.push_back("part");
}

}  // namespace lorgnette::synth
