// The shared camera model on the host: look-at framing, projection and ray directions agree, and
// distortion round-trips through the iterative undistortion.
#include "kernels/common/camera_types.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

TEST(CameraTypes, LookAtPutsTheTargetAtTheImageCentreWithAnOrthonormalFrame) {
  Camera c = camera_look_at(lgn_vec3(1.0f, 2.0f, 3.0f), lgn_vec3(0.2f, 0.1f, -0.5f), lgn_vec3(0, 1, 0), 40.0f,
                            320, 240);
  float u, v;
  float depth = camera_project(&c, lgn_vec3(0.2f, 0.1f, -0.5f), &u, &v);
  EXPECT_NEAR(u, 160.0f, 1e-3f);
  EXPECT_NEAR(v, 120.0f, 1e-3f);
  EXPECT_NEAR(depth, std::sqrt(0.8f * 0.8f + 1.9f * 1.9f + 3.5f * 3.5f), 1e-4f);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      float dot = 0;
      for (int r = 0; r < 3; ++r) dot += c.c2w[4 * r + a] * c.c2w[4 * r + b];
      EXPECT_NEAR(dot, a == b ? 1.0f : 0.0f, 1e-5f);
    }
  EXPECT_GT(c.c2w[5], 0.0f);  // camera up keeps the world's up direction
  // Vertical field of view: the top edge of the image is 20 degrees above the axis.
  LgnVec3 top = camera_ray_dir(&c, 160.0f, 0.0f);
  LgnVec3 mid = camera_ray_dir(&c, 160.0f, 120.0f);
  float cosang = top.x * mid.x + top.y * mid.y + top.z * mid.z;
  EXPECT_NEAR(std::acos(cosang) * 180.0f / 3.14159265f, 20.0f, 1e-3f);
}

TEST(CameraTypes, ProjectionInvertsRayDirectionsWithDistortion) {
  Camera c = camera_look_at(lgn_vec3(0, 0, 4), lgn_vec3(0, 0, 0), lgn_vec3(0, 1, 0), 50.0f, 512, 384);
  c.k1 = -0.12f, c.k2 = 0.03f, c.p1 = 0.001f, c.p2 = -0.002f;
  for (float u : {10.5f, 200.0f, 500.0f})
    for (float v : {5.5f, 190.0f, 380.0f}) {
      LgnVec3 d = camera_ray_dir(&c, u, v);
      LgnVec3 o = camera_origin(&c);
      float pu, pv;
      camera_project(&c, lgn_vec3(o.x + 3 * d.x, o.y + 3 * d.y, o.z + 3 * d.z), &pu, &pv);
      // 10 fixed-point undistortion steps: sub-millipixel for this moderate distortion.
      EXPECT_NEAR(pu, u, 2e-3f);
      EXPECT_NEAR(pv, v, 2e-3f);
    }
}

}  // namespace
