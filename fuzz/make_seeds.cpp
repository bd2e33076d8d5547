// Writes small valid inputs for every fuzz target into OUT/<target>/ (the seed corpora), with the
// project's own writers wherever there is one, so the seeds follow the formats as they change.
// tools/fuzz.sh starts the fuzzers from them; the replay tests (ctest -L fuzz) run them through the
// targets. Usage: fuzz_make_seeds OUT
#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "capture/colmap_model.h"
#include "fit/placement_json.h"
#include "host/dataset/dataset.h"
#include "host/nerf/snapshot.h"
#include "mesh/gltf_writer.h"
#include "mesh/parametric.h"
#include "mesh/refpoints.h"

namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using namespace lorgnette;

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read back '" + path.string() + "'");
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void spit(const fs::path& path, const std::string& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write '" + path.string() + "'");
}

// Camera-to-world pose on a circle of radius 3 around the origin, looking at it (OpenGL axes).
Eigen::Matrix4d orbit_pose(double yaw) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
  m.block<3, 1>(0, 3) = m.block<3, 1>(0, 2) * 3.0;
  return m;
}

json pose_json(const Eigen::Matrix4d& m) {
  json rows = json::array();
  for (int r = 0; r < 4; ++r) rows.push_back({m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
  return rows;
}

// transforms.json in three dialects; the fuzz target provides img_0.png .. img_2.png (8x6).
void seed_transforms(const fs::path& out, const fs::path& scratch) {
  std::vector<Camera> cams(3);
  for (int i = 0; i < 3; ++i) {
    Camera& c = cams[i];
    c = Camera{};
    c.fx = c.fy = 7.0f;
    c.cx = 4.0f;
    c.cy = 3.0f;
    c.k1 = 0.01f;
    c.width = 8;
    c.height = 6;
    dataset::set_camera_pose(c, orbit_pose(0.4 * i));
  }
  json extra = {{"aabb_scale", 4},
                {"aabb", {{-1, -1, -1}, {1, 1, 1}}},
                {"applied_transform", {{1, 0, 0, 0}, {0, 0, 1, 0}, {0, -1, 0, 0}}}};
  dataset::write_transforms_json(scratch.string(), cams, {"img_0.png", "img_1.png", "img_2.png"}, extra);
  spit(out / "instant_ngp.json", slurp(scratch / "transforms.json"));

  json synthetic = {{"camera_angle_x", 0.69}, {"frames", json::array()}};
  for (int i = 0; i < 2; ++i)
    synthetic["frames"].push_back(
        {{"file_path", fmt::format("./img_{}", i)}, {"transform_matrix", pose_json(orbit_pose(i))}});
  spit(out / "nerf_synthetic.json", synthetic.dump(2));

  json per_frame = {
      {"camera_model", "OPENCV"}, {"scale", 1.0}, {"offset", {0.5, 0.5, 0.5}}, {"frames", json::array()}};
  for (int i = 0; i < 3; ++i)
    per_frame["frames"].push_back({{"file_path", fmt::format("img_{}.png", i)},
                                   {"fl_x", 7 + i},
                                   {"fl_y", 7.5},
                                   {"cx", 4},
                                   {"cy", 3},
                                   {"w", 8},
                                   {"h", 6},
                                   {"k1", 0.1},
                                   {"k2", 0},
                                   {"p1", 0},
                                   {"p2", 0.001},
                                   {"transform_matrix", pose_json(orbit_pose(-0.3 * i))}});
  spit(out / "per_frame_intrinsics.json", per_frame.dump());

  json masked = json::parse(slurp(scratch / "transforms.json"));  // nerfstudio's per-frame mattes
  for (size_t i = 0; i < masked["frames"].size(); ++i)
    masked["frames"][i]["mask_path"] = fmt::format("mask_{}.png", i);
  spit(out / "nerfstudio_masks.json", masked.dump(1));
}

// The smallest field configuration the validation accepts: 112 parameters.
nerf::Snapshot tiny_snapshot(uint32_t occ_res, bool with_density) {
  nerf::Snapshot s;
  s.config.levels = 1;
  s.config.features_per_level = 1;
  s.config.log2_table_size = 8;
  s.config.base_resolution = s.config.finest_resolution = 2;
  s.config.density_hidden = s.config.geo_features = s.config.color_hidden = 1;
  s.config.color_hidden_layers = s.config.sh_degree = 1;
  s.aabb.min = {-1.0f, -0.5f, -1.0f};
  s.step = 0.01f;
  for (uint64_t i = 0; i < s.config.param_count(); ++i) s.params.push_back(0.01f * float(i % 17) - 0.05f);
  s.occ = nerf::full_occupancy(occ_res);
  if (with_density) s.occ.density.assign(size_t(occ_res) * occ_res * occ_res, 0.5f);
  s.normalisation.scale = 0.5f;
  s.normalisation.offset = {0.1f, 0.2f, 0.3f};
  s.metadata.steps = 100;
  s.metadata.seed = 7;
  s.metadata.final_loss = 0.02f;
  s.metadata.dataset_path = "data/head";
  return s;
}

void seed_snapshot(const fs::path& out) {
  spit(out / "density.lnerf", nerf::encode_snapshot(tiny_snapshot(2, true)));
  spit(out / "bits_only.lnerf", nerf::encode_snapshot(tiny_snapshot(1, false)));
  nerf::Snapshot with_range = tiny_snapshot(1, false);  // the optional "view_range" header entry
  std::vector<Camera> cams(3);
  for (int i = 0; i < 3; ++i) dataset::set_camera_pose(cams[i], orbit_pose(0.4 * i - 0.4));
  with_range.view_range = nerf::view_range_from_cameras(cams, {0.0f, 0.0f, 0.0f});
  spit(out / "view_range.lnerf", nerf::encode_snapshot(with_range));
  // A version 1 file (no header checksum), as older builds wrote them: mutations of its header reach
  // the value checks and the blob table, which a version 2 header's checksum stops.
  std::string v2 = nerf::encode_snapshot(tiny_snapshot(1, true));
  uint64_t hlen = 0;
  std::memcpy(&hlen, v2.data() + 8, 8);
  json h = json::parse(v2.substr(16, hlen));
  h["version"] = 1;
  h.erase(nerf::kHeaderChecksumKey);
  std::string text = h.dump();
  uint64_t n = text.size();
  spit(out / "version1.lnerf",
       v2.substr(0, 8) + std::string(reinterpret_cast<const char*>(&n), 8) + text + v2.substr(16 + hlen));
}

// The header target's inputs: the JSON headers of the snapshot seeds.
void seed_snapshot_header(const fs::path& snapshots, const fs::path& out) {
  for (const auto& e : fs::directory_iterator(snapshots)) {
    std::string file = slurp(e.path());
    uint64_t hlen = 0;
    std::memcpy(&hlen, file.data() + 8, 8);
    spit(out / (e.path().stem().string() + ".json"), file.substr(16, hlen));
  }
}

// Reference-point sidecars as the writer makes them (file units of a .glb: metres).
void seed_refpoints(const fs::path& out) {
  mesh::RefPointsSidecar s;
  s.points = mesh::make_parametric_frame(mesh::FrameParams{}).ref;
  spit(out / "detect_units.json", mesh::refpoints_sidecar_text(s));
  s.points.g_l /= 1000.0f, s.points.g_r /= 1000.0f;
  s.mm_per_unit = 1000.0;
  spit(out / "metres.json", mesh::refpoints_sidecar_text(s));
}

void seed_colmap(const fs::path& out, const fs::path& scratch) {
  capture::ColmapModel m;
  m.cameras[1] = {1, "PINHOLE", 8, 6, {7, 7, 4, 3}};
  m.cameras[2] = {2, "OPENCV", 8, 6, {7, 7.5, 4, 3, 0.01, -0.002, 0.0001, 0.0002}};
  for (uint32_t id : {1u, 2u}) {
    capture::ColmapImage im;
    im.id = id;
    im.qvec = capture::colmap_rotation_to_qvec(orbit_pose(0.3 * id).topLeftCorner<3, 3>().transpose());
    im.tvec = {0.1 * id, -0.2, 3.0};
    im.camera_id = id;
    im.name = id == 1 ? "img 0.png" : "img_1.png";  // COLMAP names may hold spaces
    if (id == 1) {
      im.xys = {{1.5, 2.5}, {3.25, 4.0}, {6.0, 1.0}};
      im.point3d_ids = {1, -1, 2};
    }
    m.images[id] = im;
  }
  m.points[1] = {1, {0.1, 0.2, 0.3}, {255, 128, 0}, 0.5, {{1, 0}}};
  m.points[2] = {2, {-0.1, 0.0, 0.4}, {10, 20, 30}, 0.25, {{1, 2}, {2, 0}}};
  for (bool binary : {true, false}) {
    fs::path dir = scratch / (binary ? "bin" : "txt");
    capture::write_colmap_model(m, dir, binary);
    for (const auto& entry : fs::directory_iterator(dir))
      spit(out / (binary ? "colmap_binary" : "colmap_text") / entry.path().filename(), slurp(entry.path()));
  }
}

void seed_placement(const fs::path& out) {
  fit::PlacementFile p;
  p.glasses_path = "frame.glb";
  p.glasses_hash = "fnv1a64:0123456789abcdef";
  p.transform.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()).toRotationMatrix() * 0.004;
  p.transform.block<3, 1>(0, 3) = Eigen::Vector3d(0.01, 0.02, 0.5);
  p.scale = 1.02;
  p.mm_per_unit = 250;
  p.pd_mm = 63;
  p.landmarks["nose_bridge"] = {{0.0, 0.1, 0.6}, 0.8, 5};
  p.landmarks["ear_left"] = {{0.3, 0.0, 0.1}, 1.5, 3};
  p.residuals_px = {{"nose_bridge", 0.7}, {"ear_left", 1.2}};
  p.views_used = 6;
  p.views_total = 8;
  p.penetration_mm = 0.2;
  p.seconds = {{"views", 1.5}, {"landmarks", 0.25}};
  p.warnings = {"left ear estimated from the mean face"};
  p.ok = true;
  spit(out / "rigid.json", fit::to_json(p).dump(2));
  p.has_temples = true;
  p.temples.fitted = true;
  p.temples.bend.left.hinge = {65, 4, -8};
  p.temples.bend.right.hinge = {-65, 4, -8};
  p.temples.bend.left.spread_deg = 3.5;
  p.temples.bend.right.spread_deg = 2.0;
  p.temples.left = {3.5, 1.2, 0.1, 40, true};
  p.temples.right = {2.0, 0.8, 0.3, 38, false};
  spit(out / "temples.json", fit::to_json(p).dump(2));
}

// A tetrahedron in two materials (frame, lens): the small seed for every mesh format.
mesh::TriMesh tetrahedron() {
  mesh::TriMesh m;
  m.positions = {{0, 0, 0}, {0.05f, 0, 0}, {0, 0.03f, 0}, {0, 0, 0.01f}};
  m.normals = {{-1, -1, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (auto& n : m.normals) n.normalize();
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  m.triangle_material = {0, 0, 0, 1};
  m.triangle_part = {0, 0, 0, 0};
  m.part_names = {"frame"};
  m.materials.resize(2);
  m.materials[0].name = "frame";
  m.materials[1].name = "lens";
  m.materials[1].transmission = 1.0f;
  m.materials[1].is_lens = true;
  m.units_to_mm = 1000.0;
  return m;
}

std::string base64(const std::string& bytes) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
    if (i + 1 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 1])) << 8;
    if (i + 2 < bytes.size()) v |= uint8_t(bytes[i + 2]);
    out += k[v >> 18 & 63];
    out += k[v >> 12 & 63];
    out += i + 1 < bytes.size() ? k[v >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? k[v & 63] : '=';
  }
  return out;
}

// The .gltf twin of a .glb: its JSON chunk with the BIN chunk as a base64 data URI.
std::string glb_to_gltf(const std::string& glb) {
  auto u32 = [&](size_t at) {
    uint32_t v;
    std::memcpy(&v, glb.data() + at, 4);
    return v;
  };
  uint32_t json_len = u32(12), bin_len = u32(20 + json_len);
  json doc = json::parse(glb.substr(20, json_len));
  doc["buffers"][0]["uri"] =
      "data:application/octet-stream;base64," + base64(glb.substr(28 + json_len, bin_len));
  return doc.dump();
}

std::string obj_text(const mesh::TriMesh& m) {
  std::string s = "# tetrahedron\no frame\n";
  for (const auto& p : m.positions) s += fmt::format("v {} {} {}\n", p.x(), p.y(), p.z());
  for (const auto& n : m.normals) s += fmt::format("vn {} {} {}\n", n.x(), n.y(), n.z());
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    if (t == 0 || m.triangle_material[t] != m.triangle_material[t - 1])
      s += "usemtl " + m.materials[m.triangle_material[t]].name + "\n";
    const auto& f = m.triangles[t];
    s += fmt::format("f {0}//{0} {1}//{1} {2}//{2}\n", f[0] + 1, f[1] + 1, f[2] + 1);
  }
  return s;
}

std::string ply(const mesh::TriMesh& m, bool binary) {
  std::string s = fmt::format(
      "ply\nformat {} 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\n"
      "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
      binary ? "binary_little_endian" : "ascii", m.positions.size(), m.triangles.size());
  for (const auto& p : m.positions) {
    if (binary)
      s.append(reinterpret_cast<const char*>(p.data()), 12);
    else
      s += fmt::format("{} {} {}\n", p.x(), p.y(), p.z());
  }
  for (const auto& f : m.triangles) {
    if (binary) {
      s += char(3);
      s.append(reinterpret_cast<const char*>(f.data()), 12);
    } else {
      s += fmt::format("3 {} {} {}\n", f[0], f[1], f[2]);
    }
  }
  return s;
}

// The glasses target reads byte 0 as the format (% 4: glb, gltf, obj, ply).
void seed_glasses(const fs::path& out, const fs::path& scratch) {
  mesh::write_glb((scratch / "tetra.glb").string(), tetrahedron());
  std::string glb = slurp(scratch / "tetra.glb");
  spit(out / "tetra_glb", '\0' + glb);
  spit(out / "tetra_gltf", '\1' + glb_to_gltf(glb));
  spit(out / "tetra_obj", '\2' + obj_text(tetrahedron()));
  spit(out / "tetra_ply_ascii", '\3' + ply(tetrahedron(), false));
  spit(out / "tetra_ply_binary", '\3' + ply(tetrahedron(), true));
  // A real (coarse) frame, so canonicalisation and reference-point detection get past their checks.
  mesh::FrameParams params;
  params.segments = 16;
  mesh::TriMesh frame = mesh::make_parametric_frame(params).mesh;
  frame.units_to_mm = 1.0;
  mesh::write_glb((scratch / "frame.glb").string(), frame);
  spit(out / "frame_glb", '\0' + slurp(scratch / "frame.glb"));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT  (writes OUT/<fuzz target>/<seed files>)\n", argv[0]);
    return 2;
  }
  fs::path out = argv[1];
  fs::path scratch = out / ".scratch";
  try {
    fs::remove_all(scratch);
    fs::create_directories(scratch);
    seed_transforms(out / "transforms", scratch);
    seed_snapshot(out / "snapshot");
    seed_snapshot_header(out / "snapshot", out / "snapshot_header");
    seed_colmap(out, scratch);
    seed_placement(out / "placement");
    seed_glasses(out / "glasses", scratch);
    seed_refpoints(out / "refpoints");
    fs::remove_all(scratch);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_make_seeds: %s\n", e.what());
    return 1;
  }
  std::printf("seeds written to %s\n", out.c_str());
  return 0;
}
