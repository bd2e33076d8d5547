// UV convention tests: a textured quad written as glTF here (2x2 texture: red, green on the top row,
// blue, white below) is loaded and ray cast; the texel under a known point of the quad must be the
// one glTF's convention puts there ((0, 0) = top-left texel), for every way a consumer samples it
// (Embree hit uv + mesh::sample_texture). A file from a generator known to store OpenGL-convention
// UVs is flipped by the loader (FlipV::kAuto), and FlipV::kNo / kYes override that. The Lee
// Perry-Smith scan (such a file) gets its scalp at the top of its colour map.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "host/util/image_io.h"
#include "mesh/embree_scene.h"
#include "mesh/loader.h"
#include "mesh/texture.h"
#include "tests/mesh/test_paths.h"

namespace lorgnette::mesh {
namespace {

namespace fs = std::filesystem;

template <typename T>
void append(std::vector<uint8_t>& buf, const std::vector<T>& v) {
  const auto* p = reinterpret_cast<const uint8_t*>(v.data());
  buf.insert(buf.end(), p, p + v.size() * sizeof(T));
}

// Unit quad in the z = 0 plane facing +z, uv in glTF convention: the top edge (y = 1) at v = 0.
std::string write_quad(const std::string& name, const std::string& generator) {
  const fs::path dir = fs::path(LORGNETTE_TEST_TMP) / "uv_convention" / name;
  fs::create_directories(dir);
  Image tex(2, 2, 3);
  const float colours[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};  // row-major, top row first
  for (int i = 0; i < 4; ++i)
    for (int c = 0; c < 3; ++c) tex.pixels[i * 3 + c] = colours[i][c];
  write_image((dir / "tex.png").string(), tex);
  const std::vector<float> pos = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const std::vector<float> uv = {0, 1, 1, 1, 1, 0, 0, 0};
  const std::vector<uint16_t> idx = {0, 1, 2, 0, 2, 3};
  std::vector<uint8_t> bin;
  append(bin, pos), append(bin, uv), append(bin, idx);
  std::ofstream((dir / "quad.bin").string(), std::ios::binary)
      .write(reinterpret_cast<const char*>(bin.data()), bin.size());
  nlohmann::json j = {
      {"asset", {{"version", "2.0"}, {"generator", generator}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"meshes",
       {{{"primitives",
          {{{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}}}, {"indices", 2}, {"material", 0}}}}}}},
      {"materials",
       {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"metallicFactor", 0.0}}}}}},
      {"textures", {{{"source", 0}}}},
      {"images", {{{"uri", "tex.png"}}}},
      {"buffers", {{{"uri", "quad.bin"}, {"byteLength", bin.size()}}}},
      {"bufferViews",
       {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
        {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 32}},
        {{"buffer", 0}, {"byteOffset", 80}, {"byteLength", 12}}}},
      {"accessors",
       {{{"bufferView", 0},
         {"componentType", 5126},
         {"count", 4},
         {"type", "VEC3"},
         {"min", {0, 0, 0}},
         {"max", {1, 1, 0}}},
        {{"bufferView", 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}},
        {{"bufferView", 2}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}}};
  const std::string path = (dir / "quad.gltf").string();
  std::ofstream(path) << j.dump(1);
  return path;
}

// Colour seen where a ray hits the quad at (x, y); texel centres sit at uv 0.25 / 0.75.
Eigen::Vector3f colour_at(const TriMesh& m, float x, float y) {
  EmbreeScene scene(m);
  Hit h = scene.intersect(Eigen::Vector3f(x, y, 1.0f), Eigen::Vector3f(0, 0, -1));
  EXPECT_TRUE(h.hit);
  if (!h.hit) return Eigen::Vector3f::Zero();
  return sample_texture(m.textures.at(m.materials.at(h.material).base_color_texture), h.uv).head<3>();
}

// Tolerance: the texels are exact primaries through 8-bit sRGB, sampled at texel centres.
constexpr float kTol = 1e-3f;

TEST(UvConvention, GltfTopLeftTexelLandsAtTheTopLeftOfTheQuad) {
  TriMesh m = load_mesh(write_quad("plain", "lorgnette test"));
  EXPECT_TRUE(colour_at(m, 0.25f, 0.75f).isApprox(Eigen::Vector3f(1, 0, 0), kTol));  // top-left: red
  EXPECT_TRUE(colour_at(m, 0.75f, 0.75f).isApprox(Eigen::Vector3f(0, 1, 0), kTol));  // top-right: green
  EXPECT_TRUE(colour_at(m, 0.25f, 0.25f).isApprox(Eigen::Vector3f(0, 0, 1), kTol));  // bottom-left: blue
  EXPECT_TRUE(colour_at(m, 0.75f, 0.25f).isApprox(Eigen::Vector3f(1, 1, 1), kTol));  // bottom-right: white
}

TEST(UvConvention, KnownOpenGlConventionGeneratorIsFlippedAutomatically) {
  const std::string path = write_quad("js2glb", "probe js2glb.py");
  LoadReport report;
  TriMesh flipped = load_mesh(path, {}, &report);
  EXPECT_TRUE(colour_at(flipped, 0.25f, 0.75f).isApprox(Eigen::Vector3f(0, 0, 1), kTol));
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find("flipped v"), std::string::npos);
  LoadOptions as_stored;
  as_stored.flip_v = FlipV::kNo;
  EXPECT_TRUE(colour_at(load_mesh(path, as_stored), 0.25f, 0.75f).isApprox(Eigen::Vector3f(1, 0, 0), kTol));
}

TEST(UvConvention, ForcedFlipFlipsAnyFile) {
  LoadOptions forced;
  forced.flip_v = FlipV::kYes;
  TriMesh m = load_mesh(write_quad("forced", "lorgnette test"), forced);
  EXPECT_TRUE(colour_at(m, 0.25f, 0.75f).isApprox(Eigen::Vector3f(0, 0, 1), kTol));
  EXPECT_TRUE(colour_at(m, 0.75f, 0.25f).isApprox(Eigen::Vector3f(0, 1, 0), kTol));
}

TEST(UvConvention, HeadScanScalpIsAtTheTopOfItsColourMap) {
  LoadReport report;
  TriMesh m = load_mesh(test::data("heads/lee-perry-smith/LeePerrySmith.glb"), {}, &report);
  size_t top = 0, bottom = 0;
  for (size_t i = 0; i < m.positions.size(); ++i) {
    if (m.positions[i].y() > m.positions[top].y()) top = i;
    if (m.positions[i].y() < m.positions[bottom].y()) bottom = i;
  }
  // Map-COL.jpg shows the face upright: the crown in the top rows, the neck and shoulders at the bottom.
  EXPECT_LT(m.uvs[top].y(), 0.1f);
  EXPECT_GT(m.uvs[bottom].y(), 0.9f);
  EXPECT_FALSE(report.warnings.empty());
}

}  // namespace
}  // namespace lorgnette::mesh
