// Orbit and look-at cameras: the target projects to the image centre, every box corner is in view
// at the framing distance, and view 0 sits on the front direction.
#include "host/render/orbit.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace lorgnette::render;

TEST(Orbit, CamerasLookAtTheCentreAndFrameTheBox) {
  OrbitSpec spec;
  spec.center = {0.5f, 1.0f, -0.2f};
  spec.half_extent = {0.4f, 0.6f, 0.3f};
  spec.views = 8;
  spec.elevation_deg = 10.0f;
  spec.width = 160;
  spec.height = 90;
  auto cams = orbit_cameras(spec);
  ASSERT_EQ(cams.size(), 8u);
  for (const Camera& c : cams) {
    float u, v;
    float depth = camera_project(&c, lgn_vec3(spec.center[0], spec.center[1], spec.center[2]), &u, &v);
    EXPECT_GT(depth, 0.0f);
    EXPECT_NEAR(u, 80.0f, 1e-3f);
    EXPECT_NEAR(v, 45.0f, 1e-3f);
    for (int k = 0; k < 8; ++k) {
      LgnVec3 p = lgn_vec3(spec.center[0] + ((k & 1) ? 1 : -1) * spec.half_extent[0],
                           spec.center[1] + ((k & 2) ? 1 : -1) * spec.half_extent[1],
                           spec.center[2] + ((k & 4) ? 1 : -1) * spec.half_extent[2]);
      camera_project(&c, p, &u, &v);
      EXPECT_TRUE(u > 0 && u < 160 && v > 0 && v < 90) << u << "," << v;
    }
  }
  // View 0 is in front (+z), raised by the elevation.
  EXPECT_GT(cams[0].c2w[11], spec.center[2]);
  EXPECT_GT(cams[0].c2w[7], spec.center[1]);
  EXPECT_NEAR(cams[0].c2w[3], spec.center[0], 1e-5f);
}

TEST(Orbit, DegenerateInputsAreRefused) {
  EXPECT_THROW(look_at({0, 0, 0}, {0, 0, 0}, {0, 1, 0}, 10, 10, 30), std::invalid_argument);
  EXPECT_THROW(look_at({0, 1, 0}, {0, 0, 0}, {0, 1, 0}, 10, 10, 30), std::invalid_argument);
  OrbitSpec spec;
  spec.views = 0;
  EXPECT_THROW(orbit_cameras(spec), std::invalid_argument);
}
