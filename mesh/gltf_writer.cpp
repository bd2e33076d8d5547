// Binary glTF writer; see gltf_writer.h. Layout: JSON chunk + one BIN chunk holding, per primitive,
// positions, normals (optional) and indices, each 4-byte aligned.
#include "mesh/gltf_writer.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "host/util/file_write.h"

namespace lorgnette::mesh {
namespace {

using nlohmann::json;

struct BinWriter {
  std::vector<uint8_t> bin;
  json views = json::array(), accessors = json::array();

  int add_view(const void* data, size_t bytes, int target) {
    while (bin.size() % 4) bin.push_back(0);
    size_t offset = bin.size();
    bin.resize(offset + bytes);
    std::memcpy(bin.data() + offset, data, bytes);
    views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}, {"target", target}});
    return static_cast<int>(views.size()) - 1;
  }
  int add_vec3(const std::vector<Eigen::Vector3f>& v, bool minmax) {
    int view = add_view(v.data(), v.size() * sizeof(Eigen::Vector3f), 34962);
    json a = {{"bufferView", view}, {"componentType", 5126}, {"count", v.size()}, {"type", "VEC3"}};
    if (minmax) {
      Eigen::Vector3f lo = v[0], hi = v[0];
      for (const auto& p : v) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
      a["min"] = {lo.x(), lo.y(), lo.z()};
      a["max"] = {hi.x(), hi.y(), hi.z()};
    }
    accessors.push_back(a);
    return static_cast<int>(accessors.size()) - 1;
  }
  int add_indices(const std::vector<uint32_t>& idx) {
    int view = add_view(idx.data(), idx.size() * sizeof(uint32_t), 34963);
    accessors.push_back(
        {{"bufferView", view}, {"componentType", 5125}, {"count", idx.size()}, {"type", "SCALAR"}});
    return static_cast<int>(accessors.size()) - 1;
  }
};

json material_json(const Material& m) {
  json j = {{"name", m.name.empty() ? "material" : m.name},
            {"doubleSided", true},
            {"pbrMetallicRoughness",
             {{"baseColorFactor", {m.base_color.x(), m.base_color.y(), m.base_color.z(), m.alpha}},
              {"metallicFactor", m.metallic},
              {"roughnessFactor", m.roughness}}}};
  if (m.alpha < 1.0f) j["alphaMode"] = "BLEND";
  if (m.transmission > 0.0f) {
    j["extensions"]["KHR_materials_transmission"] = {{"transmissionFactor", m.transmission}};
    j["extensions"]["KHR_materials_ior"] = {{"ior", m.ior}};
    // glTF tints transmission by the base colour: store the tint there for lenses.
    j["pbrMetallicRoughness"]["baseColorFactor"] = {m.tint.x(), m.tint.y(), m.tint.z(), m.alpha};
  }
  return j;
}

// Vertices and indices of the triangles of one (part, material), re-indexed compactly.
json primitive(BinWriter& w, const TriMesh& mesh, const std::vector<size_t>& tris, int material,
               float scale) {
  std::map<int, uint32_t> remap;
  std::vector<Eigen::Vector3f> pos, nrm;
  std::vector<uint32_t> idx;
  for (size_t t : tris)
    for (int k = 0; k < 3; ++k) {
      int v = mesh.triangles[t][k];
      auto [it, fresh] = remap.emplace(v, static_cast<uint32_t>(pos.size()));
      if (fresh) {
        pos.push_back(mesh.positions[v] * scale);
        if (!mesh.normals.empty()) nrm.push_back(mesh.normals[v]);
      }
      idx.push_back(it->second);
    }
  json attrs = {{"POSITION", w.add_vec3(pos, true)}};
  if (!nrm.empty()) attrs["NORMAL"] = w.add_vec3(nrm, false);
  return {{"attributes", attrs}, {"indices", w.add_indices(idx)}, {"material", material}, {"mode", 4}};
}

}  // namespace

void write_glb(const std::string& path, const TriMesh& mesh) {
  if (mesh.triangles.empty())
    throw std::runtime_error(fmt::format("cannot write '{}': the mesh is empty", path));
  const float scale = static_cast<float>(mesh.units_to_mm / 1000.0);
  BinWriter w;
  json materials = json::array(), meshes = json::array(), nodes = json::array(), scene_nodes = json::array();
  bool transmission = false;
  for (const auto& m : mesh.materials)
    materials.push_back(material_json(m)), transmission |= m.transmission > 0;
  std::map<int, std::map<int, std::vector<size_t>>> by_part;  // part -> material -> triangles
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    by_part[t < mesh.triangle_part.size() ? mesh.triangle_part[t] : 0]
           [t < mesh.triangle_material.size() ? mesh.triangle_material[t] : 0]
               .push_back(t);
  for (const auto& [part, mats] : by_part) {
    json prims = json::array();
    for (const auto& [mat, tris] : mats) prims.push_back(primitive(w, mesh, tris, mat, scale));
    std::string name =
        part < static_cast<int>(mesh.part_names.size()) ? mesh.part_names[part] : fmt::format("part{}", part);
    meshes.push_back({{"name", name}, {"primitives", prims}});
    nodes.push_back({{"name", name}, {"mesh", meshes.size() - 1}});
    scene_nodes.push_back(nodes.size() - 1);
  }
  while (w.bin.size() % 4) w.bin.push_back(0);
  json doc = {{"asset", {{"version", "2.0"}, {"generator", "lorgnette"}}},
              {"scene", 0},
              {"scenes", {{{"nodes", scene_nodes}}}},
              {"nodes", nodes},
              {"meshes", meshes},
              {"materials", materials},
              {"accessors", w.accessors},
              {"bufferViews", w.views},
              {"buffers", {{{"byteLength", w.bin.size()}}}}};
  if (transmission) doc["extensionsUsed"] = {"KHR_materials_transmission", "KHR_materials_ior"};
  std::string js = doc.dump();
  while (js.size() % 4) js.push_back(' ');
  auto u32 = [](std::string& s, uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); };
  std::string out;
  u32(out, 0x46546C67);  // "glTF"
  u32(out, 2);
  u32(out, static_cast<uint32_t>(12 + 8 + js.size() + 8 + w.bin.size()));
  u32(out, static_cast<uint32_t>(js.size()));
  u32(out, 0x4E4F534A);  // "JSON"
  out += js;
  u32(out, static_cast<uint32_t>(w.bin.size()));
  u32(out, 0x004E4942);  // "BIN\0"
  out.append(reinterpret_cast<const char*>(w.bin.data()), w.bin.size());
  write_file_atomic(path, out);
}

}  // namespace lorgnette::mesh
