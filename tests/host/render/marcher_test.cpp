// The compositing marcher (kernels/march, host/render/marcher) on analytic scenes with closed-form
// answers, on PoCL: a constant-density slab that fills the crop box, so every segment boundary the
// marcher uses lies inside the slab and the quadrature is exact up to float rounding; the glasses
// are surface buffers written by hand (premultiplied S_c, coverage S_α, depth S_t).
//
// Tolerance: 2e-5 absolute on colours in [0, 1]. Each ray composites up to ~150 segments in float;
// the telescoping sum c(1 - prod e_i) accumulates ~1 ulp (6e-8) per segment, i.e. ~1e-5 worst case.
// The exact-depth test shows that misplacing the surface by even a quarter step changes the answer
// by more than 50x this tolerance, so the tolerance cannot hide a misplaced surface.
#include "host/render/marcher.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "host/render/analytic_field.h"
#include "host/render/orbit.h"
#include "kernels/march/march_math.h"

using namespace lorgnette;
using namespace lorgnette::render;

namespace {
constexpr float kTol = 2e-5f;
constexpr float kSigma = 1.5f;
const Vec3f kSlabRgb{0.8f, 0.3f, 0.1f};
const Vec3f kBg{0.1f, 0.2f, 0.3f};
const float kInf = std::numeric_limits<float>::infinity();

cl::Runtime& runtime() {
  static cl::Runtime rt;
  return rt;
}

struct SlabScene {
  // Crop box [-1,1]^3 filled with a slab of density kSigma; a small batch so a 32x24 image takes
  // several tiles and the wave size K adapts.
  AnalyticField field;
  VolumeScene scene;
  Camera cam = look_at({0.3f, 0.2f, 3.0f}, {0, 0, 0}, {0, 1, 0}, 32, 24, 30.0f);
  RenderOptions opts;
  explicit SlabScene(float sigma = kSigma)
      : field(runtime(), {-1, -1, -1}, {1, 1, 1}, {analytic_box({-2, -2, -2}, {2, 2, 2}, sigma, kSlabRgb)},
              1024) {
    scene.aabb_min = {-1, -1, -1};
    scene.aabb_max = {1, 1, 1};
    scene.step = 0.0137f;  // not commensurate with anything in the scene
    scene.field = &field;
    opts.background = {kBg[0], kBg[1], kBg[2]};
  }
  // The ray's entry and exit of the crop box (the same float ray the kernel builds).
  void clip(int x, int y, double* tn, double* tf) const {
    LgnVec3 o = camera_origin(&cam), d = camera_ray_dir(&cam, x + 0.5f, y + 0.5f);
    float bmin[3] = {-1, -1, -1}, bmax[3] = {1, 1, 1}, t0 = 0, t1 = 0;
    EXPECT_TRUE(march_clip_aabb(bmin, bmax, o.x, o.y, o.z, d.x, d.y, d.z, &t0, &t1));
    *tn = t0;
    *tf = t1;
  }
};

void set_surface(lorgnette::SurfaceBuffers& s, int x, int y, Vec3f rgb, float alpha, float depth) {
  size_t i = size_t(y) * s.width + x;
  for (int c = 0; c < 3; ++c) s.color_alpha[4 * i + c] = alpha * rgb[c];  // premultiplied
  s.color_alpha[4 * i + 3] = alpha;
  s.depth[i] = depth;
}

// Closed form of the slab with a surface at ts (coverage a, straight colour s) over background bg.
double slab_with_surface(double tn, double tf, double ts, double a, double s, double c, double bg) {
  double e1 = std::exp(-kSigma * (ts - tn)), e2 = std::exp(-kSigma * (tf - ts));
  return c * (1 - e1) + e1 * a * s + e1 * (1 - a) * (c * (1 - e2) + e2 * bg);
}
}  // namespace

TEST(Marcher, SlabWithoutSurfaceMatchesClosedForm) {
  SlabScene s;
  Marcher m(runtime());
  RenderResult r = m.render(s.scene, s.cam, nullptr, s.opts);
  for (int y = 0; y < 24; y += 5)
    for (int x = 0; x < 32; x += 3) {
      double tn, tf;
      s.clip(x, y, &tn, &tf);
      double T = std::exp(-kSigma * (tf - tn));
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.rgba.at(x, y, c), kSlabRgb[c] * (1 - T) + T * kBg[c], kTol);
      EXPECT_NEAR(r.rgba.at(x, y, 3), 1 - T, kTol);
      // Expected depth of an exponential distribution truncated to [tn, tf].
      double L = tf - tn, mean = tn + 1 / kSigma - L * T / (1 - T);
      EXPECT_NEAR(r.depth.at(x, y, 0), mean, 2e-3) << "midpoint quadrature of t: O(step^2)";
    }
  EXPECT_GT(r.waves, 1u);
}

// (a) An opaque plane inside the slab, at a depth that is not on the step grid.
TEST(Marcher, OpaquePlaneInsideSlabMatchesClosedForm) {
  SlabScene s;
  lorgnette::SurfaceBuffers surf(32, 24);
  const Vec3f plane{0.2f, 0.5f, 0.9f};
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 32; ++x) {
      double tn, tf;
      s.clip(x, y, &tn, &tf);
      set_surface(surf, x, y, plane, 1.0f, float(tn + 0.4137 * (tf - tn)));
    }
  Marcher m(runtime());
  RenderResult r = m.render(s.scene, s.cam, &surf, s.opts);
  for (int y = 0; y < 24; y += 2)
    for (int x = 0; x < 32; x += 3) {
      double tn, tf, ts = surf.depth[size_t(y) * 32 + x];
      s.clip(x, y, &tn, &tf);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(r.rgba.at(x, y, c), slab_with_surface(tn, tf, ts, 1, plane[c], kSlabRgb[c], kBg[c]),
                    kTol);
      EXPECT_NEAR(r.rgba.at(x, y, 3), 1.0f, kTol);
    }
}

// (b) Half coverage: the volume behind the surface shows through, weighted by T(t_s)(1 - S_α).
TEST(Marcher, HalfCoverageMatchesClosedFormWithBackgroundAndAlpha) {
  SlabScene s;
  lorgnette::SurfaceBuffers surf(32, 24);
  const Vec3f plane{0.2f, 0.5f, 0.9f};
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 32; ++x) {
      double tn, tf;
      s.clip(x, y, &tn, &tf);
      set_surface(surf, x, y, plane, 0.5f, float(tn + 0.61 * (tf - tn)));
    }
  Marcher m(runtime());
  RenderResult bg = m.render(s.scene, s.cam, &surf, s.opts);
  s.opts.alpha = true;
  RenderResult transparent = m.render(s.scene, s.cam, &surf, s.opts);
  for (int y = 1; y < 24; y += 4)
    for (int x = 0; x < 32; x += 5) {
      double tn, tf, ts = surf.depth[size_t(y) * 32 + x];
      s.clip(x, y, &tn, &tf);
      double e1 = std::exp(-kSigma * (ts - tn)), e2 = std::exp(-kSigma * (tf - ts));
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(bg.rgba.at(x, y, c), slab_with_surface(tn, tf, ts, 0.5, plane[c], kSlabRgb[c], kBg[c]),
                    kTol);
        EXPECT_NEAR(transparent.rgba.at(x, y, c),
                    slab_with_surface(tn, tf, ts, 0.5, plane[c], kSlabRgb[c], 0), kTol);
      }
      EXPECT_NEAR(transparent.rgba.at(x, y, 3), 1 - e1 * 0.5 * e2, kTol);
    }
}

// A tinted lens (per-channel transmittance F·(1 - S_α)): the volume and background behind it are
// filtered per channel, X = C(tn, ts) + T·S_c + T·(1 - S_α)·F ⊙ C'(ts, tf); in front of it nothing
// changes. Same closed form as (b) with the straight colours behind the lens multiplied by F.
TEST(Marcher, TintedLensFiltersWhatLiesBehindPerChannel) {
  SlabScene s;
  lorgnette::SurfaceBuffers surf(32, 24);
  const Vec3f lens{0.05f, 0.05f, 0.05f};
  const float a = 0.6f, filter[3] = {0.4f, 1.9f, 0.7f};  // mean 1: a green lens
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 32; ++x) {
      double tn, tf;
      s.clip(x, y, &tn, &tf);
      set_surface(surf, x, y, lens, a, float(tn + 0.37 * (tf - tn)));
      for (int c = 0; c < 3; ++c) surf.filter[3 * (size_t(y) * 32 + x) + c] = filter[c];
    }
  Marcher m(runtime());
  RenderResult r = m.render(s.scene, s.cam, &surf, s.opts);
  for (int y = 1; y < 24; y += 4)
    for (int x = 0; x < 32; x += 5) {
      double tn, tf, ts = surf.depth[size_t(y) * 32 + x];
      s.clip(x, y, &tn, &tf);
      double e1 = std::exp(-kSigma * (ts - tn)), e2 = std::exp(-kSigma * (tf - ts));
      for (int c = 0; c < 3; ++c) {
        double behind = filter[c] * (kSlabRgb[c] * (1 - e2) + e2 * kBg[c]);
        double expect = kSlabRgb[c] * (1 - e1) + e1 * a * lens[c] + e1 * (1 - a) * behind;
        EXPECT_NEAR(r.rgba.at(x, y, c), expect, kTol);
      }
      EXPECT_NEAR(r.rgba.at(x, y, 3), 1 - e1 * (1 - a) * e2, kTol) << "coverage stays the mean transmittance";
    }
}

// Exact-depth insertion: a surface half-way between two sample boundaries lands where it is.
TEST(Marcher, SurfaceBetweenTwoSamplesIsInsertedAtItsExactDepth) {
  SlabScene s;
  s.scene.step = 0.05f;  // coarse, so a misplacement would be large
  lorgnette::SurfaceBuffers surf(32, 24);
  const Vec3f plane{0.0f, 1.0f, 0.0f};
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 32; ++x) {
      double tn, tf;
      s.clip(x, y, &tn, &tf);
      set_surface(surf, x, y, plane, 0.5f, float(tn + 7.5 * 0.05));  // between samples 7 and 8
    }
  Marcher m(runtime());
  RenderResult r = m.render(s.scene, s.cam, &surf, s.opts);
  for (int y = 0; y < 24; y += 3)
    for (int x = 0; x < 32; x += 4) {
      double tn, tf, ts = surf.depth[size_t(y) * 32 + x];
      s.clip(x, y, &tn, &tf);
      double exact = slab_with_surface(tn, tf, ts, 0.5, plane[1], kSlabRgb[1], kBg[1]);
      double snapped = slab_with_surface(tn, tf, tn + 8 * 0.05, 0.5, plane[1], kSlabRgb[1], kBg[1]);
      ASSERT_GT(std::fabs(exact - snapped), 50 * kTol) << "the scene must tell the two placements apart";
      EXPECT_NEAR(r.rgba.at(x, y, 1), exact, kTol);
    }
}

namespace {
// A dense box (the "NeRF surface": T falls below 1e-4 within a step) in front half of the crop box.
struct DenseScene {
  AnalyticField field{runtime(),
                      {-1, -1, -1},
                      {1, 1, 1},
                      {analytic_box({-2, -2, 0.2f}, {2, 2, 2}, 2000.0f, {0.9f, 0.6f, 0.3f})},
                      4096};
  VolumeScene scene;
  Camera cam = look_at({0.0f, 0.1f, 3.0f}, {0, 0, 0}, {0, 1, 0}, 20, 16, 30.0f);
  RenderOptions opts;
  DenseScene() {
    scene.aabb_min = {-1, -1, -1};
    scene.aabb_max = {1, 1, 1};
    scene.step = 0.01f;
    scene.field = &field;
  }
};
}  // namespace

// (c) A plane behind an opaque NeRF surface leaves the NeRF colour unchanged.
TEST(Marcher, PlaneBehindOpaqueVolumeLeavesItUnchanged) {
  DenseScene s;
  lorgnette::SurfaceBuffers surf(20, 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 20; ++x) set_surface(surf, x, y, {0.0f, 0.0f, 1.0f}, (x % 2) ? 1.0f : 0.5f, 3.5f);
  Marcher m(runtime());
  RenderResult alone = m.render(s.scene, s.cam, nullptr, s.opts);
  RenderResult with = m.render(s.scene, s.cam, &surf, s.opts);
  for (size_t i = 0; i < alone.rgba.pixels.size(); ++i)
    EXPECT_NEAR(with.rgba.pixels[i], alone.rgba.pixels[i], 1e-4f) << "T < 1e-4 is all that may leak";
  EXPECT_NEAR(alone.rgba.at(10, 8, 0), 0.9f, 1e-3f);
}

// (d) Rays that miss the glasses give bit-for-bit the NeRF-only result, also when other rays of the
// same waves hit (which changes the wave sizes), with occupancy skipping on.
TEST(Marcher, RaysMissingTheMeshAreBitwiseNerfOnly) {
  AnalyticField field(runtime(), {-1, -1, -1}, {1, 1, 1},
                      {analytic_sphere({0.1f, 0, 0}, 0.6f, 4.0f, {0.7f, 0.2f, 0.5f}),
                       analytic_box({-0.8f, -0.8f, -0.9f}, {0.8f, 0.8f, -0.5f}, 1.0f, {0.1f, 0.9f, 0.2f})},
                      1024);
  cl::Buffer<uint32_t> bits(runtime(), field.occupancy_bits(16));
  VolumeScene scene;
  scene.aabb_min = {-1, -1, -1};
  scene.aabb_max = {1, 1, 1};
  scene.step = 0.0123f;
  scene.field = &field;
  scene.occupancy = {LGN_MARCH_OCC_LINEAR, 16, &bits};
  Camera cam = look_at({1.0f, 0.5f, 2.5f}, {0, 0, 0}, {0, 1, 0}, 24, 20, 40.0f);
  lorgnette::SurfaceBuffers surf(24, 20);
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 24; ++x)
      if ((x + 2 * y) % 3 == 0) set_surface(surf, x, y, {1, 1, 0}, (x % 2) ? 1.0f : 0.3f, 2.0f + 0.05f * y);
  Marcher m(runtime());
  RenderOptions opts;
  RenderResult alone = m.render(scene, cam, nullptr, opts);
  RenderResult with = m.render(scene, cam, &surf, opts);
  int misses = 0, changed = 0;
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 24; ++x) {
      bool hit = surf.color_alpha[4 * (size_t(y) * 24 + x) + 3] > 0;
      bool same = std::memcmp(&alone.rgba.at(x, y, 0), &with.rgba.at(x, y, 0), 4 * sizeof(float)) == 0 &&
                  std::memcmp(&alone.depth.at(x, y, 0), &with.depth.at(x, y, 0), sizeof(float)) == 0 &&
                  alone.samples.at(x, y, 0) == with.samples.at(x, y, 0);
      if (!hit) {
        EXPECT_TRUE(same) << "pixel " << x << "," << y;
        ++misses;
      } else {
        changed += !same;
      }
    }
  EXPECT_GT(misses, 200);
  EXPECT_GT(changed, 100) << "the hit pixels must actually show the glasses";
}

// (e) Early termination: an opaque plane in the middle of the slab halves the samples taken.
TEST(Marcher, OpaquePlaneTerminatesRaysEarly) {
  SlabScene s(0.2f);  // thin: T stays high, so only the plane can end the rays early
  lorgnette::SurfaceBuffers surf(32, 24);
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 32; ++x) {
      double tn, tf;
      s.clip(x, y, &tn, &tf);
      set_surface(surf, x, y, {1, 0, 0}, 1.0f, float(0.5 * (tn + tf)));
    }
  Marcher m(runtime());
  RenderResult alone = m.render(s.scene, s.cam, nullptr, s.opts);
  RenderResult with = m.render(s.scene, s.cam, &surf, s.opts);
  EXPECT_LT(with.samples_evaluated, alone.samples_evaluated * 0.55);
  EXPECT_GT(with.samples_evaluated, alone.samples_evaluated * 0.45);
  EXPECT_LT(with.samples_composited, alone.samples_composited * 0.55);
  EXPECT_EQ(alone.rays, 32u * 24u);
}

// (f) Occlusion both ways: an opaque plane in front of the slab hides it; a plane behind it is seen
// through it.
TEST(Marcher, PlanesInFrontAndBehindTheVolumeOccludeInBothOrders) {
  SlabScene s;
  lorgnette::SurfaceBuffers surf(32, 24);
  const Vec3f front{1.0f, 0.0f, 0.0f}, back{0.0f, 0.0f, 1.0f};
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 32; ++x) {
      double tn, tf;
      s.clip(x, y, &tn, &tf);
      if (x < 16) {
        set_surface(surf, x, y, front, 1.0f, float(0.5 * tn));
      } else {
        set_surface(surf, x, y, back, 1.0f, float(tf + 0.3));
      }
    }
  Marcher m(runtime());
  RenderResult r = m.render(s.scene, s.cam, &surf, s.opts);
  for (int y = 0; y < 24; y += 3)
    for (int x = 0; x < 32; x += 2) {
      double tn, tf;
      s.clip(x, y, &tn, &tf);
      double T = std::exp(-kSigma * (tf - tn));
      for (int c = 0; c < 3; ++c) {
        double expect = x < 16 ? front[c] : kSlabRgb[c] * (1 - T) + T * back[c];
        EXPECT_NEAR(r.rgba.at(x, y, c), expect, kTol) << x << "," << y;
      }
      if (x < 16) {
        EXPECT_EQ(r.samples.at(x, y, 0), 0.0f) << "nothing behind an opaque surface is marched";
      }
    }
}

// Empty-space skipping changes nothing visible and takes fewer samples.
TEST(Marcher, OccupancyGridSkipsEmptySpaceWithoutChangingTheImage) {
  AnalyticField field(runtime(), {-1, -1, -1}, {1, 1, 1},
                      {analytic_sphere({0, 0, 0}, 0.5f, 3.0f, {0.2f, 0.4f, 0.8f})}, 2048);
  cl::Buffer<uint32_t> bits(runtime(), field.occupancy_bits(32));
  VolumeScene scene;
  scene.aabb_min = {-1, -1, -1};
  scene.aabb_max = {1, 1, 1};
  scene.step = 0.01f;
  scene.field = &field;
  Camera cam = look_at({0.4f, 0.3f, 2.8f}, {0, 0, 0}, {0, 1, 0}, 24, 24, 45.0f);
  Marcher m(runtime());
  RenderResult dense = m.render(scene, cam, nullptr, {});
  scene.occupancy = {LGN_MARCH_OCC_LINEAR, 32, &bits};
  RenderResult skipping = m.render(scene, cam, nullptr, {});
  for (size_t i = 0; i < dense.rgba.pixels.size(); ++i)
    EXPECT_NEAR(skipping.rgba.pixels[i], dense.rgba.pixels[i], 1e-4f)
        << "same sample grid, t summed differently";
  EXPECT_LT(skipping.samples_evaluated, dense.samples_evaluated / 2);
  EXPECT_GT(dense.rgba.at(12, 12, 2), 0.5f);
}

TEST(Marcher, SeveralSamplesPerPixelAverageAndBadInputsAreRefused) {
  SlabScene s;
  Marcher m(runtime());
  s.opts.spp = 4;
  RenderResult r = m.render(s.scene, s.cam, nullptr, s.opts);
  EXPECT_EQ(r.rays, 4u * 32u * 24u);
  double tn, tf;
  s.clip(16, 12, &tn, &tf);
  double T = std::exp(-kSigma * (tf - tn));
  EXPECT_NEAR(r.rgba.at(16, 12, 0), kSlabRgb[0] * (1 - T) + T * kBg[0], 2e-3)
      << "sub-pixel rays differ slightly";
  lorgnette::SurfaceBuffers wrong(16, 16);
  EXPECT_THROW(m.render(s.scene, s.cam, &wrong, s.opts), std::invalid_argument);
  s.opts.spp = 0;
  EXPECT_THROW(m.render(s.scene, s.cam, nullptr, s.opts), std::invalid_argument);
  VolumeScene none;
  EXPECT_THROW(m.render(none, s.cam, nullptr, {}), std::invalid_argument);
}
