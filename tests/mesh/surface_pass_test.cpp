// Surface pass tests on analytic scenes: jittered stratified coverage of a half-plane edge through
// a pixel centre converges to 0.5 with the stated error for N samples; an opaque plane gives full
// coverage and exact depths; an empty view gives zero coverage and +inf depth; a clear lens at
// normal incidence covers exactly its Fresnel reflectance; results are deterministic and do not
// depend on the thread count; tracing only inside the frame's projected screen bounds gives the
// buffers of tracing every pixel, bit for bit.
#include "mesh/surface_pass.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "mesh/disney_brdf.h"
#include "mesh/parametric.h"

namespace lorgnette::mesh {
namespace {

Material opaque() {
  Material m;
  m.name = "white";
  m.base_color = {1, 1, 1};
  return m;
}

// One triangle in the z = z0 plane whose edge A-B runs through the origin at angle `theta` and that
// covers the side its normal points to, up to `size` from the origin.
TriMesh half_plane(float theta, float z0, float size, Material mat) {
  Eigen::Vector3f t(std::cos(theta), std::sin(theta), 0), n(-std::sin(theta), std::cos(theta), 0);
  TriMesh m;
  m.positions = {-size * t + Eigen::Vector3f(0, 0, z0), size * t + Eigen::Vector3f(0, 0, z0),
                 size * n + Eigen::Vector3f(0, 0, z0)};
  m.triangles = {{0, 1, 2}};
  m.triangle_material = {0};
  m.triangle_part = {0};
  m.materials = {mat};
  m.part_names = {"half-plane"};
  return m;
}

// 3x3 camera at the origin looking down -z: pixel (1, 1) is centred on the optical axis.
Camera tiny_camera(float f = 100.0f) {
  return look_at_camera({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 2.0f * std::atan(1.5f / f) * 180.0f / kPi, 3, 3);
}

TEST(SurfacePass, HalfPlaneEdgeCoverageConvergesToHalf) {
  // Any line through a pixel's centre halves it, so the exact coverage is 0.5. The edge is slanted
  // (0.3 rad) so that it cuts strata at arbitrary places. With n stratified samples about
  // 2 sqrt(n) strata are cut, each a Bernoulli(<= 1/4) / n term: RMS error <= sqrt(2 sqrt(n) / 4) / n
  // (0.71 for n = 1, 0.25 for 4, 0.088 for 16, 0.031 for 64). Measured over 400 seeds, the RMS must
  // be within that bound and the mean within 4 standard errors of 0.5 (no bias).
  SurfacePass pass(half_plane(0.3f, -1.0f, 10.0f, opaque()), Eigen::Matrix4f::Identity());
  const int seeds = 400;
  double previous_rms = 1.0;
  for (int n : {1, 4, 16, 64}) {
    double sum = 0, sum2 = 0;
    for (int s = 0; s < seeds; ++s) {
      SurfaceParams p;
      p.samples_per_pixel = n;
      p.seed = 1000 + s;
      p.threads = 1;
      p.lighting.key_shadow = 0;
      SurfaceBuffers b = pass.render(tiny_camera(), p);
      double a = b.color_alpha[4 * (1 * 3 + 1) + 3];
      sum += a, sum2 += (a - 0.5) * (a - 0.5);
    }
    double mean = sum / seeds, rms = std::sqrt(sum2 / seeds);
    double bound = std::sqrt(2.0 * std::sqrt(n) / 4.0) / n;
    std::printf("n = %2d: mean coverage %.4f, RMS error %.4f (bound %.4f)\n", n, mean, rms, bound);
    EXPECT_LE(rms, bound) << n;
    EXPECT_NEAR(mean, 0.5, 4.0 * std::max(rms, 1e-3) / std::sqrt(seeds)) << n;
    EXPECT_LT(rms, previous_rms) << n;  // converges
    previous_rms = rms;
  }
}

TEST(SurfacePass, OpaquePlaneFullCoverageExactDepth) {
  SurfacePass pass(half_plane(0.0f, -2.0f, 1000.0f, opaque()), Eigen::Matrix4f::Identity());
  // Only the upper half-plane y > 0 is covered: move the camera down so the whole view sees it.
  Camera cam = look_at_camera({0, 5, 0}, {0, 5, -1}, {0, 1, 0}, 40.0f, 32, 24);
  SurfaceParams p;
  p.samples_per_pixel = 4;
  SurfaceBuffers b = pass.render(cam, p);
  for (size_t i = 0; i < b.pixel_count(); ++i) {
    EXPECT_FLOAT_EQ(b.color_alpha[4 * i + 3], 1.0f);
    EXPECT_GE(b.depth[i], 2.0f - 1e-5f);
  }
  // Pixel (16, 12) has its corner on the optical axis: its samples lie within sqrt(2) pixels of
  // the axis, so the nearest depth is in [2, 2 / cos(sqrt(2) / f)] (+1e-5 float rounding).
  size_t centre = static_cast<size_t>(12) * 32 + 16;
  EXPECT_GE(b.depth[centre], 2.0f - 1e-5f);
  EXPECT_LE(b.depth[centre], 2.0f / std::cos(std::sqrt(2.0f) / cam.fy) + 1e-5f);
  // Premultiplied colour of an opaque surface under bounded lighting: finite, positive, < 2.
  for (int k = 0; k < 3; ++k) {
    EXPECT_GT(b.color_alpha[4 * centre + k], 0.05f);
    EXPECT_LT(b.color_alpha[4 * centre + k], 2.0f);
  }
}

TEST(SurfacePass, EmptyViewHasNoCoverageAndInfiniteDepth) {
  SurfacePass pass(half_plane(0.0f, -2.0f, 1.0f, opaque()), Eigen::Matrix4f::Identity());
  Camera cam = look_at_camera({0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 40.0f, 16, 16);  // looking away
  SurfaceBuffers b = pass.render(cam, {});
  for (size_t i = 0; i < b.pixel_count(); ++i) {
    EXPECT_EQ(b.color_alpha[4 * i + 3], 0.0f);
    EXPECT_EQ(b.color_alpha[4 * i + 0], 0.0f);
    EXPECT_TRUE(std::isinf(b.depth[i]));
  }
}

TEST(SurfacePass, ClearLensCoversItsFresnelReflectance) {
  Material lens;
  lens.name = "lens";
  lens.transmission = 1.0f;
  lens.tint = {1, 1, 1};
  lens.roughness = 0.0f;
  lens.ior = 1.5f;
  lens.is_lens = true;
  SurfacePass pass(half_plane(0.0f, -1.0f, 1000.0f, lens), Eigen::Matrix4f::Identity());
  Camera cam = look_at_camera({0, 5, 0}, {0, 5, -1}, {0, 1, 0}, 1.0f, 3, 3);  // rays within 0.5 deg of normal
  SurfaceParams p;
  p.samples_per_pixel = 16;
  SurfaceBuffers b = pass.render(cam, p);
  // Coverage = 1 - (1 - F) with F = 0.04 at normal incidence (within 1e-4 for 0.5 degrees).
  EXPECT_NEAR(b.color_alpha[4 * 4 + 3], 0.04f, 1e-4f);
  // The eyes stay visible: the reflected colour is F times the environment (< 0.05 here).
  EXPECT_LT(b.color_alpha[4 * 4 + 0], 0.05f);
  EXPECT_TRUE(std::isfinite(b.depth[4]));
}

TEST(SurfacePass, TintedLensPassesItsTintPerChannel) {
  // Normal incidence on a green lens: per-channel transmittance (1 - F) * tint with F = 0.04, so
  // 1 - S_α is its mean and the filter is tint / mean(tint) (both within 1e-4 for 0.5 degrees).
  Material lens;
  lens.name = "lens";
  lens.transmission = 1.0f;
  lens.tint = {0.3f, 0.8f, 0.4f};
  lens.roughness = 0.0f;
  lens.ior = 1.5f;
  lens.is_lens = true;
  SurfacePass pass(half_plane(0.0f, -1.0f, 1000.0f, lens), Eigen::Matrix4f::Identity());
  Camera cam = look_at_camera({0, 5, 0}, {0, 5, -1}, {0, 1, 0}, 1.0f, 3, 3);
  SurfaceParams p;
  p.samples_per_pixel = 4;
  SurfaceBuffers b = pass.render(cam, p);
  const float mean_tint = 0.5f;
  EXPECT_NEAR(b.color_alpha[4 * 4 + 3], 1.0f - 0.96f * mean_tint, 1e-4f);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(b.filter[3 * 4 + k], lens.tint[k] / mean_tint, 1e-4f);
  // A pixel that misses everything (none here: the lens fills the view) would keep F = 1; an opaque
  // frame too: checked on the half plane's other side below.
  SurfacePass opaque_pass(half_plane(0.0f, -1.0f, 1000.0f, opaque()), Eigen::Matrix4f::Identity());
  SurfaceBuffers o = opaque_pass.render(cam, p);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(o.filter[3 * 4 + k], 1.0f);
}

TEST(SurfacePass, DeterministicAndThreadCountIndependent) {
  ParametricFrame f = make_parametric_frame({});
  Eigen::Matrix4f place = Eigen::Matrix4f::Identity();
  place.topLeftCorner<3, 3>() *= 0.001f;  // mm -> m
  SurfacePass pass(f.mesh, place);
  Camera cam = look_at_camera({0.05f, 0.03f, 0.4f}, {0, 0, -0.03f}, {0, 1, 0}, 30.0f, 64, 48);
  SurfaceParams p;
  p.samples_per_pixel = 4;
  p.threads = 1;
  SurfaceBuffers a = pass.render(cam, p);
  p.threads = 2;
  SurfaceBuffers b = pass.render(cam, p);
  EXPECT_EQ(a.color_alpha, b.color_alpha);
  EXPECT_EQ(a.depth, b.depth);
  double coverage = 0;
  for (size_t i = 0; i < a.pixel_count(); ++i) coverage += a.color_alpha[4 * i + 3];
  EXPECT_GT(coverage, 10.0);  // the frame is in view
}

// Every pixel's samples are seeded by the pixel alone, so the clipped pass must equal the full one
// bit for bit: where the full pass hits nothing (S_α = 0, S_t = +inf, F = 1, the buffers' initial
// values) and where it hits (the same rays are traced). Cameras: the frame seen from the front and
// from the side at two distances (the rectangle must skip most pixels), and from inside its box (a
// grid point behind the camera: the whole image is traced).
TEST(SurfacePass, ScreenBoundsPassEqualsFullPass) {
  ParametricFrame f = make_parametric_frame({});
  Eigen::Matrix4f place = Eigen::Matrix4f::Identity();
  place.topLeftCorner<3, 3>() *= 0.001f;  // mm -> m
  SurfacePass pass(f.mesh, place);
  struct View {
    Eigen::Vector3f eye;
    bool expect_clip;
  };
  const View views[] = {{{0.02f, 0.01f, 0.5f}, true},
                        {{0.45f, 0.05f, 0.25f}, true},
                        {{0.01f, -0.03f, 1.2f}, true},
                        {{0.0f, 0.0f, -0.01f}, false}};
  for (const View& v : views) {
    Camera cam = look_at_camera(v.eye, {0, 0, -0.03f}, {0, 1, 0}, 40.0f, 160, 90);
    std::array<int, 4> r = pass.screen_rect(cam);
    const int area = (r[2] - r[0]) * (r[3] - r[1]);
    if (v.expect_clip)
      EXPECT_LT(area, 160 * 90 / 2) << "the rectangle should skip most of the image";
    else
      EXPECT_EQ(area, 160 * 90) << "a grid point behind the camera must give the whole image";
    SurfaceParams p;
    p.samples_per_pixel = 2;
    SurfaceBuffers clipped = pass.render(cam, p);
    p.clip_to_bounds = false;
    SurfaceBuffers full = pass.render(cam, p);
    size_t hits = 0;
    for (size_t i = 0; i < full.pixel_count(); ++i) hits += full.color_alpha[4 * i + 3] > 0.0f;
    EXPECT_GT(hits, 20u) << "the frame should be in view";
    // memcmp-equal: == on floats would also pass for -0 vs 0 and fail on NaN.
    ASSERT_EQ(clipped.color_alpha.size(), full.color_alpha.size());
    EXPECT_EQ(0,
              std::memcmp(clipped.color_alpha.data(), full.color_alpha.data(), 4 * full.color_alpha.size()));
    EXPECT_EQ(0, std::memcmp(clipped.depth.data(), full.depth.data(), 4 * full.depth.size()));
    EXPECT_EQ(0, std::memcmp(clipped.filter.data(), full.filter.data(), 4 * full.filter.size()));
  }
}

TEST(SurfacePass, BadParametersAreClearErrors) {
  SurfacePass pass(half_plane(0.0f, -2.0f, 1.0f, opaque()), Eigen::Matrix4f::Identity());
  SurfaceParams p;
  p.samples_per_pixel = 0;
  EXPECT_THROW(pass.render(tiny_camera(), p), std::runtime_error);
  Camera empty = tiny_camera();
  empty.width = 0;
  EXPECT_THROW(pass.render(empty, {}), std::runtime_error);
}

}  // namespace
}  // namespace lorgnette::mesh
