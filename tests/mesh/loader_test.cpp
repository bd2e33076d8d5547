// Loader tests: every shared glasses model and the textured head load with the expected parts,
// triangles, lens materials and bounding boxes (in file units, after node transforms); bad files
// (missing, corrupt, empty, a directory) give clear errors naming the problem. The memory entry
// point reads what the file entry point reads.
#include "mesh/loader.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "mesh/gltf_writer.h"
#include "tests/mesh/test_paths.h"

namespace lorgnette::mesh {
namespace {

Eigen::AlignedBox3f box_of(const TriMesh& m) {
  Eigen::AlignedBox3f b;
  for (const auto& p : m.positions) b.extend(p);
  return b;
}

struct Expected {
  const char* name;
  size_t parts, triangles, lens_materials;
  Eigen::Vector3f size;  // bounding-box extents in file units (after node transforms)
};

// Regression values recorded with this loader (node transforms applied, units as in the file: the
// Sketchfab exports' "metres" are arbitrary units, which canonicalisation sorts out).
const Expected kExpected[] = {
    {"glasses-01", 8, 76013, 1, {167.268f, 40.554f, 165.874f}},
    {"glasses-03", 3, 14036, 1, {3.70802f, 1.15164f, 3.75277f}},
    {"glasses-04", 6, 30168, 1, {0.146206f, 0.0501373f, 0.16217f}},
    {"glasses-05", 5, 55168, 2, {13.96424f, 5.22416f, 14.39501f}},
    {"glasses-06", 3, 42496, 1, {14.6684f, 4.25362f, 12.48601f}},
    {"glasses-07", 4, 18904, 1, {2.09587f, 0.865618f, 2.114067f}},
    {"khronos", 8, 13396, 2, {0.150501f, 0.0576224f, 0.161463f}},
};

TEST(Loader, SharedGlassesLoadWithExpectedPartsAndBounds) {
  for (const auto& g : test::shared_glasses()) {
    SCOPED_TRACE(g.name);
    LoadReport report;
    TriMesh m = load_mesh(test::data(g.path), {}, &report);
    const Expected* e = nullptr;
    for (const auto& x : kExpected)
      if (std::string(x.name) == g.name) e = &x;
    ASSERT_NE(e, nullptr);
    EXPECT_EQ(m.part_names.size(), e->parts);
    EXPECT_EQ(m.triangle_count(), e->triangles);
    size_t lenses = 0;
    for (const auto& mat : m.materials) lenses += mat.is_lens;
    EXPECT_EQ(lenses, e->lens_materials);
    EXPECT_EQ(m.triangle_material.size(), m.triangle_count());
    EXPECT_EQ(m.triangle_part.size(), m.triangle_count());
    EXPECT_DOUBLE_EQ(m.units_to_mm, 1000.0);  // glTF declares metres
    // 1e-4 relative: float accumulation of the node transforms and 6-digit recorded values.
    Eigen::Vector3f size = box_of(m).sizes();
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(size[k], e->size[k], 1e-4f * e->size.norm()) << k;
  }
}

TEST(Loader, KhronosLensesUseTransmissionAndNamedParts) {
  TriMesh m = load_mesh(test::data("glasses/khronos-sunglasses/SunglassesKhronos.glb"));
  std::vector<std::string> want = {"EarhookRight", "TempleRight", "EarhookLeft",    "TempleLeft",
                                   "Nosepads",     "Frames",      "LensesInterior", "LensesExterior"};
  EXPECT_EQ(m.part_names, want);
  for (const auto& mat : m.materials) {
    if (mat.name == "lens_exterior") {
      EXPECT_TRUE(mat.is_lens);
      EXPECT_FLOAT_EQ(mat.transmission, 1.0f);
    }
    if (mat.name == "nose_pads") {
      EXPECT_FALSE(mat.is_lens);  // transmissive, but not a lens
    }
  }
  EXPECT_EQ(m.textures.size(), 1u);  // the ear hooks' embedded base-colour texture
}

TEST(Loader, EmbeddedHeadTextureDecodes) {
  TriMesh m = load_mesh(test::data("heads/lee-perry-smith/LeePerrySmith.glb"));
  EXPECT_EQ(m.vertex_count() > 9000, true);
  EXPECT_EQ(m.triangle_count(), 17672u);
  ASSERT_EQ(m.textures.size(), 1u);
  EXPECT_GT(m.textures[0].width, 256);
  EXPECT_EQ(m.uvs.size(), m.vertex_count());
  EXPECT_EQ(m.normals.size(), m.vertex_count());
}

void expect_error(const std::string& path, const std::string& fragment) {
  try {
    load_mesh(path);
    ADD_FAILURE() << "no exception for " << path;
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(Loader, BadFilesGiveClearErrors) {
  namespace fs = std::filesystem;
  fs::path dir = fs::path(LORGNETTE_TEST_TMP) / "mesh_loader";
  fs::create_directories(dir);
  expect_error((dir / "missing.glb").string(), "does not exist");
  std::ofstream((dir / "empty.glb").string()).close();
  expect_error((dir / "empty.glb").string(), "empty");
  std::ofstream((dir / "corrupt.glb").string(), std::ios::binary)
      << "glTF\x02\0\0\0garbage that is not a glb";
  expect_error((dir / "corrupt.glb").string(), "cannot load mesh");
  std::ofstream((dir / "points.ply").string())
      << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "end_header\n0 0 0\n1 0 0\n0 1 0\n";
  expect_error((dir / "points.ply").string(), "");  // no faces: Assimp or our empty check refuses it
  expect_error(dir.string(), "directory");
}

TEST(Loader, ObjWithMtlAndPlyLoad) {
  namespace fs = std::filesystem;
  fs::path dir = fs::path(LORGNETTE_TEST_TMP) / "mesh_loader";
  fs::create_directories(dir);
  std::ofstream((dir / "quad.mtl").string()) << "newmtl red\nKd 1 0 0\nd 1\n";
  std::ofstream((dir / "quad.obj").string())
      << "mtllib quad.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
         "f 1 2 3 4\n";
  LoadReport report;
  TriMesh obj = load_mesh((dir / "quad.obj").string(), {}, &report);
  EXPECT_EQ(obj.triangle_count(), 2u);  // the quad is triangulated
  EXPECT_DOUBLE_EQ(obj.units_to_mm, 1.0);
  bool red = false;
  for (const auto& m : obj.materials) red |= m.base_color.isApprox(Eigen::Vector3f(1, 0, 0));
  EXPECT_TRUE(red);
  std::ofstream((dir / "tri.ply").string())
      << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n2 0 0\n0 3 0\n3 0 1 2\n";
  TriMesh ply = load_mesh((dir / "tri.ply").string());
  EXPECT_EQ(ply.triangle_count(), 1u);
  EXPECT_NEAR(box_of(ply).sizes().y(), 3.0f, 1e-6f);
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(Loader, FromMemoryMatchesTheFile) {
  const std::string path = test::data("glasses/khronos-sunglasses/SunglassesKhronos.glb");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "team data missing: " << path;
  TriMesh file = load_mesh(path);
  std::string bytes = slurp(path);
  TriMesh memory = load_mesh_from_memory(bytes.data(), bytes.size(), "GLB");
  ASSERT_EQ(memory.triangle_count(), file.triangle_count());
  EXPECT_EQ(memory.part_names, file.part_names);
  ASSERT_EQ(memory.materials.size(), file.materials.size());
  for (size_t i = 0; i < file.materials.size(); ++i)
    EXPECT_EQ(memory.materials[i].is_lens, file.materials[i].is_lens);
  EXPECT_EQ(memory.textures.size(), file.textures.size());
  EXPECT_TRUE(box_of(memory).isApprox(box_of(file)));
  EXPECT_DOUBLE_EQ(memory.units_to_mm, file.units_to_mm);
  EXPECT_THROW(load_mesh_from_memory(bytes.data(), bytes.size(), "fbx"), std::runtime_error);
}

// Found by fuzzing (fuzz/regressions/glasses/): Assimp 5.2 trusts a GLB chunk length (21 bytes
// asked for 4 GB) and dereferences a null face for an indexed LINE_LOOP with an index out of range,
// also in JSON that is not valid UTF-8.
TEST(Loader, GlbLengthsMustFitAndLineLoopsAreRefused) {
  const std::string huge(
      "glTF\x02\0\0\0\x60\x45\0\0\x54\x11\xff\xff"
      "JSON",
      20);
  try {
    load_mesh_from_memory(huge.data(), huge.size(), "glb");
    ADD_FAILURE() << "a GLB chunk longer than the file was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bytes"), std::string::npos) << e.what();
  }
  const std::string cut("glTF\x02\0\xffJSON", 11);  // shorter than the header (read past its end)
  EXPECT_THROW(load_mesh_from_memory(cut.data(), cut.size(), "glb"), std::runtime_error);
  namespace fs = std::filesystem;
  fs::path dir = fs::path(LORGNETTE_TEST_TMP) / "mesh_loader";
  fs::create_directories(dir);
  TriMesh tri;
  tri.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  tri.triangles = {{0, 1, 2}};
  tri.triangle_material = {0};
  tri.triangle_part = {0};
  tri.part_names = {"part"};
  tri.materials = {Material{"m"}};
  write_glb((dir / "tri.glb").string(), tri);
  std::string glb = slurp((dir / "tri.glb").string());
  EXPECT_EQ(load_mesh_from_memory(glb.data(), glb.size(), "glb").triangle_count(), 1u);
  size_t mode = glb.find("\"mode\":4");
  ASSERT_NE(mode, std::string::npos);
  glb[mode + 7] = '2';  // LINE_LOOP, same length
  try {
    load_mesh_from_memory(glb.data(), glb.size(), "glb");
    ADD_FAILURE() << "an indexed LINE_LOOP was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("LINE_LOOP"), std::string::npos) << e.what();
  }
  // The same with invalid UTF-8 in a name: Assimp reads such JSON, so the check must not skip it.
  size_t name = glb.find("\"part\"");
  ASSERT_NE(name, std::string::npos);
  glb[name + 1] = '\xfa';
  try {
    load_mesh_from_memory(glb.data(), glb.size(), "glb");
    ADD_FAILURE() << "an indexed LINE_LOOP in invalid UTF-8 JSON was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("LINE_LOOP"), std::string::npos) << e.what();
  }
}

// Found by fuzzing (fuzz/regressions/glasses/): Assimp 5.2 loops forever on a PLY header without
// end_header or with a stray control character before it, allocates whatever a count says, and
// aborts the process on faces without vertices; the loader refuses all of them (mesh/file_checks.h).
// CRLF line ends stay fine.
TEST(Loader, MalformedPlyIsRefusedNotHungOrAborted) {
  namespace fs = std::filesystem;
  fs::path dir = fs::path(LORGNETTE_TEST_TMP) / "mesh_loader";
  fs::create_directories(dir);
  std::ofstream((dir / "truncated.ply").string())
      << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n";
  expect_error((dir / "truncated.ply").string(), "no end_header");
  const std::string header =
      "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\nproperty float y\r\n"
      "property float z\r\nelement face 1\r\nproperty list uchar int vertex_indices\r\n";
  const std::string body = "end_header\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n";
  std::string crlf = header + body;
  EXPECT_EQ(load_mesh_from_memory(crlf.data(), crlf.size(), "ply").triangle_count(), 1u);
  for (const char* stray : {"\r\r", "\f", "\v"}) {
    std::string bad = header + stray + body;
    try {
      load_mesh_from_memory(bad.data(), bad.size(), "ply");
      ADD_FAILURE() << "a control character in the header was accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("control character"), std::string::npos) << e.what();
    }
  }
  // Counts the data does not hold (Assimp allocated 17 GB for the first list, 26 GB for the vertices).
  auto ply = [](const std::string& vertices, const std::string& data) {
    return "ply\nformat ascii 1.0\nelement vertex " + vertices +
           "\nproperty float x\nproperty float y\nproperty float z\nelement face 1\n"
           "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n" +
           data;
  };
  for (const std::string& bad :
       {ply("3", "2160668374 0 1 2\n"), ply("3", "4 0 1 2\n"), ply("2160668374", "3 0 1 2\n")}) {
    try {
      load_mesh_from_memory(bad.data(), bad.size(), "ply");
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("not a valid PLY file"), std::string::npos) << e.what();
    }
  }
  const std::string good = ply("3", "3 0 1 2\n");
  EXPECT_EQ(load_mesh_from_memory(good.data(), good.size(), "ply").triangle_count(), 1u);
  // Under another format's name it goes to that format's importer alone (by its first bytes it
  // reached the PLY reader, past the check, and hung it).
  const std::string truncated = "ply\nformat ascii 1.0\nelement vertex 4\n";
  EXPECT_THROW(load_mesh_from_memory(truncated.data(), truncated.size(), "gltf"), std::runtime_error);
  // Binary files of either byte order with mixed property types pass the check and load.
  for (bool big : {false, true}) {
    std::string bin = std::string("ply\nformat binary_") + (big ? "big" : "little") +
                      "_endian 1.0\ncomment test\nelement vertex 3\nproperty float x\nproperty float y\n"
                      "property float z\nproperty uchar red\nproperty uint8 green\nproperty uchar blue\n"
                      "element face 1\nproperty list uchar uint vertex_indices\nend_header\n";
    auto put = [&](const void* p, size_t n) {
      std::string b(static_cast<const char*>(p), n);
      if (big) std::reverse(b.begin(), b.end());
      bin += b;
    };
    const float xyz[3][3] = {{0, 0, 0}, {2, 0, 0}, {0, 3, 0}};
    for (const auto& v : xyz) {
      for (float c : v) put(&c, 4);
      bin += std::string("\x10\x20\x30", 3);
    }
    bin += '\x03';
    for (uint32_t i = 0; i < 3; ++i) put(&i, 4);
    TriMesh m = load_mesh_from_memory(bin.data(), bin.size(), "ply");
    EXPECT_EQ(m.triangle_count(), 1u) << (big ? "big" : "little") << " endian";
    EXPECT_NEAR(box_of(m).sizes().y(), 3.0f, 1e-6f);
    bin.pop_back();  // truncated: the last index is incomplete
    EXPECT_THROW(load_mesh_from_memory(bin.data(), bin.size(), "ply"), std::runtime_error);
  }
  std::string empty_faces =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n0\n";
  try {
    load_mesh_from_memory(empty_faces.data(), empty_faces.size(), "ply");
    ADD_FAILURE() << "a face without vertices was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("has no vertices"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace lorgnette::mesh
