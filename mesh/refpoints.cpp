// Reference point detection on canonical frames and the sidecar JSON; see refpoints.h.
#include "mesh/refpoints.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "host/util/bounds.h"
#include "host/util/file_kind.h"
#include "host/util/image_io.h"
#include "mesh/canonical.h"
#include "mesh/frame_samples.h"

namespace lorgnette::mesh {
namespace {

float percentile(std::vector<float> v, float q) {
  if (v.empty()) return std::numeric_limits<float>::quiet_NaN();
  size_t k = std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

Eigen::Vector3f mirror(const Eigen::Vector3f& p) { return {-p.x(), p.y(), p.z()}; }

Eigen::Vector3f detect_bridge(const std::vector<Eigen::Vector3f>& pts, float width, float front,
                              RefPoints& out) {
  float half = std::max(1.5f, 0.012f * width);
  std::vector<float> ys, zs;
  for (const auto& p : pts)
    if (std::abs(p.x()) < half && p.z() > front - 35.0f) ys.push_back(p.y());
  if (ys.size() < 10) {
    out.notes.push_back("no bridge geometry on the symmetry plane: g_c placed at the front centre");
    return {0.0f, 0.0f, front};
  }
  float y_under = percentile(ys, 0.02f);  // 2 %: robust to a few stray samples
  for (const auto& p : pts)
    if (std::abs(p.x()) < half && p.z() > front - 35.0f && p.y() < y_under + 1.5f) zs.push_back(p.z());
  return {0.0f, y_under, percentile(zs, 0.05f)};
}

// Underside profile of one temple (side = +1 left, -1 right) in 3 mm depth bins, front to back.
struct Bin {
  float z, y_under, x_mean;
  int n;
};

std::vector<Bin> temple_profile(const std::vector<Eigen::Vector3f>& pts, float width, float front, int side) {
  const float bin = 3.0f, start = front - 25.0f;
  std::map<int, std::vector<Eigen::Vector3f>> bins;
  for (const auto& p : pts)
    if (side * p.x() > 0.25f * width && p.z() < start)
      bins[static_cast<int>((start - p.z()) / bin)].push_back(p);
  std::vector<Bin> out;
  for (auto& [k, v] : bins) {
    if (v.size() < 4) continue;
    std::vector<float> ys;
    float xs = 0;
    for (const auto& p : v) ys.push_back(p.y()), xs += p.x();
    out.push_back(
        {start - (k + 0.5f) * bin, percentile(ys, 0.05f), xs / v.size(), static_cast<int>(v.size())});
  }
  return out;
}

Eigen::Vector3f detect_ear_point(const std::vector<Bin>& prof, RefPoints& out, const char* name) {
  if (prof.size() < 3)
    throw std::runtime_error(
        fmt::format("no temple found on the {} side: is this a glasses frame with temples "
                    "(arms)? Give the points in a .refpoints.json sidecar",
                    name));
  // The ear sits well behind the hinge: search the back 55 % of the temple, against the chord from
  // the 30 % point to the tip (the front end is skewed by end pieces and hinges hanging down).
  const size_t first = static_cast<size_t>(0.30f * (prof.size() - 1));
  const size_t search = static_cast<size_t>(0.45f * (prof.size() - 1));
  const Bin& a = prof[first];
  const Bin& b = prof.back();
  size_t knee = 0;
  float best = -1e9f;
  for (size_t i = search; i < prof.size(); ++i) {
    float t = (prof[i].z - a.z) / (b.z - a.z);
    float above = prof[i].y_under - (a.y_under + t * (b.y_under - a.y_under));
    if (above > best) best = above, knee = i;
  }
  if (best < 3.0f) {  // straight temple: no bend to rest on
    knee = static_cast<size_t>(0.75f * (prof.size() - 1));
    out.notes.push_back(fmt::format("{} temple is straight: ear point at 75 % of its depth", name));
  }
  return {prof[knee].x_mean, prof[knee].y_under, prof[knee].z};
}

// A point in the mesh file's coordinates: three numbers within +-kMeshCoord (bounds.h), so 1e300
// (infinite as a float) or a NaN never reaches the canonical frame.
Eigen::Vector3f read_vec(const nlohmann::json& j, const char* key, const std::string& path) {
  if (!j.contains(key) || !j[key].is_array() || j[key].size() != 3)
    throw std::runtime_error(fmt::format("sidecar '{}': '{}' must be an array of 3 numbers", path, key));
  Eigen::Vector3f v;
  for (int k = 0; k < 3; ++k) {
    const nlohmann::json& x = j[key][k];
    if (!x.is_number())
      throw std::runtime_error(fmt::format("sidecar '{}': '{}' must be an array of 3 numbers", path, key));
    double d = x.get<double>();
    if (!(std::abs(d) <= bounds::kMeshCoord))
      throw OutOfRange(fmt::format(
          "sidecar '{}': '{}' must hold coordinates within +-{:g} (the mesh file's units), found {}; fix "
          "or delete the sidecar",
          path, key, bounds::kMeshCoord, x.dump()));
    v[k] = static_cast<float>(d);
  }
  return v;
}

}  // namespace

std::vector<bool> lens_triangles(const TriMesh& mesh) {
  std::vector<bool> out(mesh.triangles.size(), false);
  for (size_t i = 0; i < out.size() && i < mesh.triangle_material.size(); ++i) {
    int m = mesh.triangle_material[i];
    out[i] = m >= 0 && m < static_cast<int>(mesh.materials.size()) && mesh.materials[m].is_lens;
  }
  return out;
}

RefPoints detect_refpoints(const TriMesh& mesh) {
  std::vector<Eigen::Vector3f> pts = sample_frame_surface(mesh, 80000, 11u);
  Eigen::AlignedBox3f box;
  for (const auto& p : pts) box.extend(p);
  const float width = box.sizes().x(), front = box.max().z();
  RefPoints r;
  r.source = "detected";
  r.g_c = detect_bridge(pts, width, front, r);
  Eigen::Vector3f l = detect_ear_point(temple_profile(pts, width, front, +1), r, "left");
  Eigen::Vector3f rr = detect_ear_point(temple_profile(pts, width, front, -1), r, "right");
  float asym = (l - mirror(rr)).norm();
  if (asym > 5.0f) r.notes.push_back(fmt::format("temples are asymmetric by {:.1f} mm; averaged", asym));
  r.g_l = 0.5f * (l + mirror(rr));
  r.g_r = mirror(r.g_l);
  return r;
}

std::string sidecar_path(const std::string& mesh_path) { return mesh_path + ".refpoints.json"; }

std::optional<RefPointsSidecar> read_refpoints_sidecar(const std::string& mesh_path) {
  std::string path = sidecar_path(mesh_path);
  if (!std::filesystem::exists(path)) return std::nullopt;
  return parse_refpoints_sidecar(read_regular_file(path, "sidecar"), path);
}

RefPointsSidecar parse_refpoints_sidecar(std::string_view text, const std::string& path) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const std::exception& e) {
    throw std::runtime_error(
        fmt::format("sidecar '{}' is not valid JSON ({}); fix or delete it", path, e.what()));
  }
  if (!j.is_object()) throw std::runtime_error(fmt::format("sidecar '{}' must hold a JSON object", path));
  if (j.contains("space") && !j["space"].is_string())
    throw std::runtime_error(fmt::format("sidecar '{}': space must be \"file\"", path));
  RefPointsSidecar s;
  s.space = j.value("space", std::string("file"));
  if (s.space != "file")
    throw std::runtime_error(
        fmt::format("sidecar '{}': space must be \"file\" (the mesh file's own coordinates), "
                    "not \"{}\"",
                    path, s.space));
  if (j.contains("mm_per_unit")) {
    if (!j["mm_per_unit"].is_number())
      throw std::runtime_error(fmt::format("sidecar '{}': 'mm_per_unit' must be a number", path));
    s.mm_per_unit = j["mm_per_unit"].get<double>();
    Bound key = bounds::kMmPerUnit;  // the flag's range, named by the file's key
    key.flag = "mm_per_unit";
    if (s.mm_per_unit != 0.0) check_file_bound(path, key, s.mm_per_unit);
  }
  s.points.g_c = read_vec(j, "g_c", path);
  s.points.g_l = read_vec(j, "g_l", path);
  s.points.g_r = read_vec(j, "g_r", path);
  s.points.source = "sidecar";
  return s;
}

std::string refpoints_sidecar_text(const RefPointsSidecar& s) {
  auto v = [](const Eigen::Vector3f& p) { return nlohmann::json::array({p.x(), p.y(), p.z()}); };
  nlohmann::json j = {{"version", 1},
                      {"space", s.space},
                      {"g_c", v(s.points.g_c)},
                      {"g_l", v(s.points.g_l)},
                      {"g_r", v(s.points.g_r)}};
  if (s.mm_per_unit > 0) j["mm_per_unit"] = s.mm_per_unit;
  return j.dump(2) + "\n";
}

void write_refpoints_sidecar(const std::string& mesh_path, const RefPointsSidecar& s) {
  write_text_file_atomic(sidecar_path(mesh_path), refpoints_sidecar_text(s));
}

}  // namespace lorgnette::mesh
