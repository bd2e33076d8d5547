// Glasses canonicalisation + reference point regression on the seven shared frames: canonical
// orientation (identity for these files), units, plausible symmetric points, sizes, and two
// models' points against hand-checked values. Set LORGNETTE_MESH_PREVIEWS=1 to also write the
// preview sheets into the test temp dir for checking by eye.
#include "mesh/glasses.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "mesh/preview.h"
#include "tests/mesh/test_paths.h"

namespace lorgnette::mesh {
namespace {

TEST(Glasses, SharedFramesGivePlausibleSymmetricPoints) {
  const bool previews = std::getenv("LORGNETTE_MESH_PREVIEWS") != nullptr;
  for (const auto& s : test::shared_glasses()) {
    SCOPED_TRACE(s.name);
    Glasses g = load_glasses(test::data(s.path));
    const auto& r = g.ref;
    const auto& m = g.metrics;
    std::printf("%s: W %.1f H %.1f D %.1f lens %.1f x %.1f bridge %.1f temple %.1f | gl %.1f %.1f %.1f\n",
                s.name, m.total_width_mm, m.total_height_mm, m.total_depth_mm, m.lens_width_mm,
                m.lens_height_mm, m.bridge_mm, m.temple_length_mm, r.g_l.x(), r.g_l.y(), r.g_l.z());
    for (auto& n : g.notes) std::printf("   %s\n", n.c_str());
    if (previews) {
      std::filesystem::path dir = std::filesystem::path(LORGNETTE_TEST_TMP) / "mesh_previews";
      std::filesystem::create_directories(dir);
      write_image((dir / (std::string(s.name) + ".png")).string(), render_glasses_preview(g));
    }
    EXPECT_FLOAT_EQ(r.g_c.norm(), 0.0f);  // the canonical origin
    EXPECT_FLOAT_EQ(r.g_l.x(), -r.g_r.x());
    EXPECT_FLOAT_EQ(r.g_l.y(), r.g_r.y());
    EXPECT_FLOAT_EQ(r.g_l.z(), r.g_r.z());
    // Plausible adult anatomy relative to the nose bridge: ears 55-85 mm to the side, 25 mm below
    // to 12 mm above, 60-130 mm behind (every preview was also checked by eye).
    EXPECT_GT(r.g_l.x(), 55.0f);
    EXPECT_LT(r.g_l.x(), 85.0f);
    EXPECT_GT(r.g_l.y(), -25.0f);
    EXPECT_LT(r.g_l.y(), 12.0f);
    EXPECT_GT(r.g_l.z(), -130.0f);
    EXPECT_LT(r.g_l.z(), -60.0f);
    EXPECT_GT(m.total_width_mm, 105.0f);
    EXPECT_LT(m.total_width_mm, 185.0f);
    EXPECT_GT(m.lens_width_mm, 40.0f);
    EXPECT_LT(m.lens_width_mm, 70.0f);
    EXPECT_GT(m.bridge_mm, 8.0f);
    EXPECT_LT(m.bridge_mm, 25.0f);
    EXPECT_GT(m.temple_length_mm, 120.0f);
    EXPECT_LT(m.temple_length_mm, 185.0f);
    EXPECT_FALSE(m.lens_parts.empty());
    // The Sketchfab/Khronos exports are already y-up, z-forward: canonicalisation keeps the axes.
    EXPECT_TRUE(g.canonical.rotation.isIdentity(1e-6f)) << g.canonical.rotation;
  }
}

// Hand-checked on the preview sheets (side view: the point sits where the temple starts to bend
// down over the ear; top view: on the temple): the Khronos sunglasses (metres, exact units) and the
// Sketchfab "Plastic Sunglasses" (glasses-04, metres). 3 mm: the detector's sampling resolution
// (3 mm depth bins, 80k random surface samples with a fixed seed).
TEST(Glasses, HandCheckedReferencePoints) {
  struct Case {
    const char* path;
    Eigen::Vector3f g_l;
    float lens, bridge;
  };
  const Case cases[] = {
      {"glasses/khronos-sunglasses/SunglassesKhronos.glb", {68.8f, -15.9f, -118.7f}, 67.2f, 9.5f},
      {"glasses/glasses-04/scene.gltf", {70.7f, 3.3f, -101.7f}, 51.5f, 18.5f}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.path);
    Glasses g = load_glasses(test::data(c.path));
    EXPECT_LT((g.ref.g_l - c.g_l).norm(), 3.0f) << g.ref.g_l.transpose();
    EXPECT_LT((g.ref.g_r - Eigen::Vector3f(-c.g_l.x(), c.g_l.y(), c.g_l.z())).norm(), 3.0f);
    EXPECT_NEAR(g.metrics.lens_width_mm, c.lens, 0.5f);  // from the lens parts' extents: exact
    EXPECT_NEAR(g.metrics.bridge_mm, c.bridge, 0.5f);
  }
}

TEST(Glasses, UnitsAreDetectedOrAssumedAndSaidSo) {
  Glasses cm = load_glasses(test::data("glasses/glasses-05/scene.gltf"));
  EXPECT_DOUBLE_EQ(cm.canonical.mm_per_unit, 10.0);  // Sketchfab FBX export in centimetres
  Glasses unknown = load_glasses(test::data("glasses/glasses-07/scene.gltf"));
  EXPECT_NE(unknown.canonical.units.find("assumed"), std::string::npos);
  EXPECT_NEAR(unknown.metrics.total_width_mm, 140.0f, 0.5f);
  GlassesOptions given;
  given.mm_per_unit = 50.0;
  Glasses forced = load_glasses(test::data("glasses/glasses-07/scene.gltf"), given);
  EXPECT_DOUBLE_EQ(forced.canonical.mm_per_unit, 50.0);
}

TEST(Glasses, RotatedFileIsCanonicalisedBackToTheSameFrame) {
  // The Khronos file turned 90 degrees about x (z-up, as many CAD exports) and in millimetres:
  // orientation and unit detection must undo both and find the same points (3 mm as above).
  TriMesh m = load_mesh(test::data("glasses/khronos-sunglasses/SunglassesKhronos.glb"));
  Eigen::Matrix4f xf = Eigen::Matrix4f::Identity();
  xf.topLeftCorner<3, 3>() =
      1000.0f * Eigen::AngleAxisf(0.5f * 3.14159265f, Eigen::Vector3f::UnitX()).toRotationMatrix();
  transform_mesh(m, xf);
  m.units_to_mm = 1.0;
  Glasses ref = load_glasses(test::data("glasses/khronos-sunglasses/SunglassesKhronos.glb"));
  Glasses g = canonicalize_glasses(std::move(m), {});
  EXPECT_DOUBLE_EQ(g.canonical.mm_per_unit, 1.0);
  EXPECT_LT((g.ref.g_l - ref.ref.g_l).norm(), 3.0f) << g.ref.g_l.transpose();
  EXPECT_NEAR(g.metrics.total_width_mm, ref.metrics.total_width_mm, 0.5f);
}

TEST(Glasses, MalformedSidecarIsAClearError) {
  namespace fs = std::filesystem;
  fs::path dir = fs::path(LORGNETTE_TEST_TMP) / "mesh_sidecar";
  fs::create_directories(dir);
  fs::path mesh = dir / "frame.glb";
  fs::copy_file(test::data("glasses/khronos-sunglasses/SunglassesKhronos.glb"), mesh,
                fs::copy_options::overwrite_existing);  // a temp copy, so that a sidecar can sit beside it
  std::ofstream(sidecar_path(mesh.string())) << "{\"g_c\": [0, 0]}";
  try {
    load_glasses(mesh.string());
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("g_c"), std::string::npos) << e.what();
  }
  fs::remove(sidecar_path(mesh.string()));
}

}  // namespace
}  // namespace lorgnette::mesh
