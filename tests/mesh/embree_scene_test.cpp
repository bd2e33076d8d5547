// Embree scene tests on analytic geometry: a textured quad with known hit distance, barycentrics,
// normals and uv; placement transforms (scale + translation); occlusion; many rays on threads
// agree with one-by-one tracing; the head scan loads and is hit where its bounding box says.
#include "mesh/embree_scene.h"

#include <gtest/gtest.h>

#include "mesh/loader.h"
#include "tests/mesh/test_paths.h"

namespace lorgnette::mesh {
namespace {

// Unit quad in the z = 0 plane, [0,1]^2, two triangles, uv = (x, y), normals +z.
TriMesh quad() {
  TriMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.normals.assign(4, Eigen::Vector3f(0, 0, 1));
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.triangle_material = {0, 0};
  m.triangle_part = {0, 0};
  m.materials.resize(1);
  m.part_names = {"quad"};
  return m;
}

TEST(EmbreeScene, HitsQuadWithExactDistanceNormalAndUv) {
  EmbreeScene scene(quad());
  Hit h = scene.intersect({0.25f, 0.75f, 5.0f}, {0, 0, -1});
  ASSERT_TRUE(h.hit);
  // Single-precision ray/triangle arithmetic on O(1) numbers: 1e-5 absolute.
  EXPECT_NEAR(h.t, 5.0f, 1e-5f);
  EXPECT_NEAR(h.uv.x(), 0.25f, 1e-5f);
  EXPECT_NEAR(h.uv.y(), 0.75f, 1e-5f);
  EXPECT_NEAR(h.geometric_normal.z(), 1.0f, 1e-6f);
  EXPECT_NEAR(h.shading_normal.z(), 1.0f, 1e-6f);
  EXPECT_EQ(h.triangle, 1);
  EXPECT_EQ(h.material, 0);
  EXPECT_EQ(h.part, 0);
  EXPECT_FALSE(scene.intersect({1.5f, 0.5f, 5.0f}, {0, 0, -1}).hit);
  EXPECT_FALSE(scene.intersect({0.5f, 0.5f, 5.0f}, {0, 0, -1}, 0.0f, 4.0f).hit);  // tfar respected
}

TEST(EmbreeScene, PlacementTransformScalesAndMoves) {
  Eigen::Matrix4f xf = Eigen::Matrix4f::Identity();
  xf.topLeftCorner<3, 3>() *= 0.001f;  // mm -> m
  xf.block<3, 1>(0, 3) = Eigen::Vector3f(1, 2, 3);
  EmbreeScene scene(quad(), xf);
  Hit h = scene.intersect({1.0005f, 2.0005f, 10.0f}, {0, 0, -1});
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 7.0f, 1e-5f);
  EXPECT_NEAR(h.uv.x(), 0.5f, 1e-3f);  // 1e-3: float resolution of 1.0005 at the 1e-3 m scale
  EXPECT_TRUE(scene.occluded({1.0005f, 2.0005f, 10.0f}, {0, 0, -1}));
  EXPECT_FALSE(scene.occluded({1.0005f, 2.0005f, 10.0f}, {0, 0, 1}));
}

TEST(EmbreeScene, ManyRaysOnThreadsMatchSingleRays) {
  EmbreeScene scene(quad());
  std::vector<RayQuery> rays;
  for (int i = 0; i < 5000; ++i) {
    float x = -0.2f + 1.4f * (i % 71) / 70.0f, y = -0.2f + 1.4f * (i / 71) / 70.0f;
    rays.push_back({{x, y, 2.0f}, {0, 0, -1}});
  }
  auto hits = scene.intersect_many(rays, 2);
  for (size_t i = 0; i < rays.size(); ++i) {
    Hit h = scene.intersect(rays[i].origin, rays[i].dir);
    ASSERT_EQ(h.hit, hits[i].hit) << i;
    if (h.hit) {
      EXPECT_EQ(h.t, hits[i].t);
    }
  }
}

TEST(EmbreeScene, EmptyMeshIsAClearError) {
  try {
    EmbreeScene scene{TriMesh{}};
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos);
  }
}

TEST(EmbreeScene, HeadScanIsHitFromTheFront) {
  TriMesh head = load_mesh(test::data("heads/lee-perry-smith/LeePerrySmith.glb"));
  EXPECT_FALSE(head.textures.empty());
  EXPECT_FALSE(head.uvs.empty());
  EmbreeScene scene(std::move(head));
  auto box = scene.bounds();
  Eigen::Vector3f c = box.center();
  // The face looks towards +z: a ray from the front through the box centre hits the front half.
  Hit h = scene.intersect({c.x(), c.y(), box.max().z() + 10.0f}, {0, 0, -1});
  ASSERT_TRUE(h.hit);
  EXPECT_GT(h.position.z(), c.z());
  EXPECT_GT(h.shading_normal.z(), 0.0f);
}

}  // namespace
}  // namespace lorgnette::mesh
