// The fused marcher (kernels/march/march_fused.cl), forced on PoCL, against the wavefront marcher
// (the reference: march.cl, tested on closed forms in marcher_test.cpp) and against the same closed
// forms for the surface insertion and early termination.
//
// Tolerances. Analytic scenes: both paths take the same segments (same ends, midpoints, skips),
// evaluate the same LGN_INLINE field code and composite by the same LGN_INLINE step, so the only
// freedom is the compiler's (fused multiply-add contraction in two different kernels): colour,
// alpha and depth within 1e-6 absolute (measured: 0 on PoCL), per-pixel sample counts equal.
// Trained NeRF: the fused kernel runs the network per sample in scalar code (mlp_layer1.h), the
// wavefront path through the CPU kernels in float16 lanes; the sums run in the same order with
// fma, but vector and scalar exp/sigmoid may differ by an ulp, which exp(raw) and the composite
// carry through: colour and alpha within 1e-4 absolute (as the training/inference paths test,
// tests/host/nerf/paths_agree_test.cpp), depth within 1e-4 relative, sample counts equal on all
// but a few pixels (a T < 1e-4 decided by an ulp). Measured on PoCL: 6e-8 in colour, 0 in depth,
// no sample-count difference. The tolerance still catches every error of the march itself, which
// the analytic scenes pin down exactly (a surface snapped to a step boundary, a skipped cell, a
// missed early exit change colours by far more than 1e-4 there).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "host/nerf/sizing.h"
#include "host/nerf/trainer.h"
#include "host/render/analytic_field.h"
#include "host/render/marcher.h"
#include "host/render/orbit.h"
#include "host/render/renderer.h"
#include "kernels/march/march_math.h"
#include "tests/host/nerf/synthetic_scene.h"

using namespace lorgnette;
using namespace lorgnette::render;

namespace {
constexpr float kSigma = 1.5f;
const Vec3f kSlabRgb{0.8f, 0.3f, 0.1f};
const Vec3f kBg{0.1f, 0.2f, 0.3f};

cl::Runtime& runtime() {
  static cl::Runtime rt;
  return rt;
}

RenderOptions forced(MarcherKind kind, RenderOptions o = {}) {
  o.marcher = kind;
  return o;
}

struct Diff {
  double rgba = 0, depth = 0;
  int sample_mismatches = 0;
};

Diff compare(const RenderResult& a, const RenderResult& b) {
  Diff d;
  for (size_t i = 0; i < a.rgba.pixels.size(); ++i)
    d.rgba = std::max(d.rgba, double(std::fabs(a.rgba.pixels[i] - b.rgba.pixels[i])));
  for (size_t i = 0; i < a.depth.pixels.size(); ++i) {
    d.depth = std::max(d.depth, double(std::fabs(a.depth.pixels[i] - b.depth.pixels[i])) /
                                    std::max(1.0, double(std::fabs(a.depth.pixels[i]))));
    d.sample_mismatches += a.samples.pixels[i] != b.samples.pixels[i];
  }
  return d;
}

void set_surface(lorgnette::SurfaceBuffers& s, int x, int y, Vec3f rgb, float alpha, float depth) {
  size_t i = size_t(y) * s.width + x;
  for (int c = 0; c < 3; ++c) s.color_alpha[4 * i + c] = alpha * rgb[c];  // premultiplied
  s.color_alpha[4 * i + 3] = alpha;
  s.depth[i] = depth;
}

// The slab of marcher_test.cpp: density kSigma filling the crop box [-1, 1]^3.
struct SlabScene {
  AnalyticField field;
  VolumeScene scene;
  Camera cam = look_at({0.3f, 0.2f, 3.0f}, {0, 0, 0}, {0, 1, 0}, 32, 24, 30.0f);
  RenderOptions opts;
  explicit SlabScene(float sigma = kSigma)
      : field(runtime(), {-1, -1, -1}, {1, 1, 1}, {analytic_box({-2, -2, -2}, {2, 2, 2}, sigma, kSlabRgb)},
              1024) {
    scene.aabb_min = {-1, -1, -1};
    scene.aabb_max = {1, 1, 1};
    scene.step = 0.0137f;
    scene.field = &field;
    opts.background = kBg;
  }
  void clip(int x, int y, double* tn, double* tf) const {
    LgnVec3 o = camera_origin(&cam), d = camera_ray_dir(&cam, x + 0.5f, y + 0.5f);
    float bmin[3] = {-1, -1, -1}, bmax[3] = {1, 1, 1}, t0 = 0, t1 = 0;
    EXPECT_TRUE(march_clip_aabb(bmin, bmax, o.x, o.y, o.z, d.x, d.y, d.z, &t0, &t1));
    *tn = t0;
    *tf = t1;
  }
};

double slab_with_surface(double tn, double tf, double ts, double a, double s, double c, double bg) {
  double e1 = std::exp(-kSigma * (ts - tn)), e2 = std::exp(-kSigma * (tf - ts));
  return c * (1 - e1) + e1 * a * s + e1 * (1 - a) * (c * (1 - e2) + e2 * bg);
}

void expect_same(const RenderResult& wave, const RenderResult& fused, const char* what) {
  Diff d = compare(wave, fused);
  std::printf("%s: max |d rgba| %.3g, max d depth %.3g, sample-count mismatches %d\n", what, d.rgba, d.depth,
              d.sample_mismatches);
  EXPECT_LE(d.rgba, 1e-6) << what;
  EXPECT_LE(d.depth, 1e-6) << what;
  EXPECT_EQ(d.sample_mismatches, 0) << what;
  EXPECT_EQ(wave.samples_composited, fused.samples_composited) << what;
  EXPECT_EQ(fused.samples_evaluated, fused.samples_composited)
      << "the fused kernel evaluates what it composites";
}
}  // namespace

// Every surface case of marcher_test.cpp at once (opaque, half coverage, a tinted lens, planes in
// front of and behind the volume, rays without a surface), with and without a background.
TEST(FusedMarcher, SlabWithSurfacesMatchesWavefront) {
  SlabScene s;
  lorgnette::SurfaceBuffers surf(32, 24);
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 32; ++x) {
      double tn, tf;
      s.clip(x, y, &tn, &tf);
      const int kind = (x + 3 * y) % 6;
      const float f = float(0.1 + 0.8 * ((x * 7 + y * 3) % 11) / 10.0);  // where along the ray
      if (kind == 0) set_surface(surf, x, y, {0.2f, 0.5f, 0.9f}, 1.0f, float(tn + f * (tf - tn)));
      if (kind == 1) set_surface(surf, x, y, {0.9f, 0.1f, 0.4f}, 0.5f, float(tn + f * (tf - tn)));
      if (kind == 2) {
        set_surface(surf, x, y, {0.05f, 0.05f, 0.05f}, 0.6f, float(tn + f * (tf - tn)));
        const float filter[3] = {0.4f, 1.9f, 0.7f};
        for (int c = 0; c < 3; ++c) surf.filter[3 * (size_t(y) * 32 + x) + c] = filter[c];
      }
      if (kind == 3) set_surface(surf, x, y, {1, 0, 0}, 1.0f, float(0.5 * tn));  // in front of the box
      if (kind == 4) set_surface(surf, x, y, {0, 0, 1}, 0.7f, float(tf + 0.3));  // behind it
    }
  Marcher m(runtime());
  for (bool alpha : {false, true}) {
    s.opts.alpha = alpha;
    RenderResult wave = m.render(s.scene, s.cam, &surf, forced(MarcherKind::Wavefront, s.opts));
    RenderResult fused = m.render(s.scene, s.cam, &surf, forced(MarcherKind::Fused, s.opts));
    expect_same(wave, fused, alpha ? "slab + surfaces, alpha" : "slab + surfaces, background");
    EXPECT_EQ(fused.waves, 1u) << "one launch for the frame";
    EXPECT_GT(wave.waves, 1u);
  }
  // The frame pipeline's band (hybrid_frame.h): rows outside [8, 16) are marched before the surface
  // pass has finished, the band after it; one launch per range.
  lorgnette::SurfaceBuffers band(32, 24);
  for (size_t i = 8 * 32; i < 16 * 32; ++i) {
    for (int c = 0; c < 4; ++c) band.color_alpha[4 * i + c] = surf.color_alpha[4 * i + c];
    for (int c = 0; c < 3; ++c) band.filter[3 * i + c] = surf.filter[3 * i + c];
    band.depth[i] = surf.depth[i];
  }
  PendingSurfaces pending;
  pending.row_begin = 8;
  pending.row_end = 16;
  pending.wait = [&band]() -> const lorgnette::SurfaceBuffers& { return band; };
  s.opts.alpha = false;
  RenderResult wave = m.render(s.scene, s.cam, pending, forced(MarcherKind::Wavefront, s.opts));
  RenderResult fused = m.render(s.scene, s.cam, pending, forced(MarcherKind::Fused, s.opts));
  expect_same(wave, fused, "slab + surfaces in a band of rows");
  EXPECT_EQ(fused.waves, 3u) << "rows above, rows below, then the band";
}

// Occupancy skipping and a dense volume that ends rays by T < 1e-4, several passes per pixel.
TEST(FusedMarcher, OccupancySkippingAndEarlyTerminationMatchWavefront) {
  AnalyticField field(runtime(), {-1, -1, -1}, {1, 1, 1},
                      {analytic_sphere({0.1f, 0, 0}, 0.6f, 40.0f, {0.7f, 0.2f, 0.5f}),
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
  RenderOptions o;
  o.spp = 3;
  Marcher m(runtime());
  RenderResult wave = m.render(scene, cam, &surf, forced(MarcherKind::Wavefront, o));
  RenderResult fused = m.render(scene, cam, &surf, forced(MarcherKind::Fused, o));
  expect_same(wave, fused, "sphere + box, occupancy 16^3, 3 spp");
  EXPECT_LT(fused.samples_evaluated, wave.samples_evaluated)
      << "the wavefront path evaluates some samples past termination within a wave; the fused one none";
  RenderResult alone_w = m.render(scene, cam, nullptr, forced(MarcherKind::Wavefront, o));
  RenderResult alone_f = m.render(scene, cam, nullptr, forced(MarcherKind::Fused, o));
  expect_same(alone_w, alone_f, "sphere + box, no surface");
}

// Exact-depth insertion through the fused kernel, on the closed form (as marcher_test.cpp): a
// surface half-way between two sample boundaries, where snapping it to a boundary would be off by
// more than 50x the tolerance.
TEST(FusedMarcher, SurfaceBetweenTwoSamplesIsInsertedAtItsExactDepth) {
  SlabScene s;
  s.scene.step = 0.05f;
  lorgnette::SurfaceBuffers surf(32, 24);
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 32; ++x) {
      double tn, tf;
      s.clip(x, y, &tn, &tf);
      set_surface(surf, x, y, {0.0f, 1.0f, 0.0f}, 0.5f, float(tn + 7.5 * 0.05));
    }
  Marcher m(runtime());
  RenderResult r = m.render(s.scene, s.cam, &surf, forced(MarcherKind::Fused, s.opts));
  constexpr double kTol = 2e-5;  // marcher_test.cpp's: float accumulation over <= 150 segments
  for (int y = 0; y < 24; y += 3)
    for (int x = 0; x < 32; x += 4) {
      double tn, tf, ts = surf.depth[size_t(y) * 32 + x];
      s.clip(x, y, &tn, &tf);
      double exact = slab_with_surface(tn, tf, ts, 0.5, 1.0, kSlabRgb[1], kBg[1]);
      double snapped = slab_with_surface(tn, tf, tn + 8 * 0.05, 0.5, 1.0, kSlabRgb[1], kBg[1]);
      ASSERT_GT(std::fabs(exact - snapped), 50 * kTol);
      EXPECT_NEAR(r.rgba.at(x, y, 1), exact, kTol);
    }
}

// Early termination through the fused kernel: an opaque plane at mid-depth halves the samples,
// and nothing behind an opaque plane in front of the box is marched.
TEST(FusedMarcher, OpaqueSurfacesEndTheMarch) {
  SlabScene s(0.2f);
  lorgnette::SurfaceBuffers mid(32, 24), front(32, 24);
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 32; ++x) {
      double tn, tf;
      s.clip(x, y, &tn, &tf);
      set_surface(mid, x, y, {1, 0, 0}, 1.0f, float(0.5 * (tn + tf)));
      set_surface(front, x, y, {0, 1, 0}, 1.0f, float(0.5 * tn));
    }
  Marcher m(runtime());
  RenderOptions o = forced(MarcherKind::Fused, s.opts);
  RenderResult alone = m.render(s.scene, s.cam, nullptr, o);
  RenderResult with = m.render(s.scene, s.cam, &mid, o);
  EXPECT_LT(with.samples_evaluated, alone.samples_evaluated * 0.55);
  EXPECT_GT(with.samples_evaluated, alone.samples_evaluated * 0.45);
  RenderResult hidden = m.render(s.scene, s.cam, &front, o);
  EXPECT_EQ(hidden.samples_composited, 0u);
  EXPECT_NEAR(hidden.rgba.at(5, 5, 1), 1.0f, 1e-6f);
}

TEST(FusedMarcher, AutoPicksTheWavefrontOnACpuAndBadWordsAreRefused) {
  SlabScene s;
  Marcher m(runtime());
  RenderResult r = m.render(s.scene, s.cam, nullptr, s.opts);
  if (runtime().device().is_gpu)
    EXPECT_EQ(r.waves, 1u);
  else
    EXPECT_GT(r.waves, 1u) << "Auto on a CPU device marches in waves";
  EXPECT_EQ(parse_marcher_kind("fused"), MarcherKind::Fused);
  EXPECT_EQ(parse_marcher_kind("wavefront"), MarcherKind::Wavefront);
  EXPECT_THROW(parse_marcher_kind("gpu"), std::invalid_argument);
}

// A NeRF trained briefly on the synthetic sphere (fixed seeds, as paths_agree_test.cpp, with a
// smaller hash table so it trains in a few seconds): hash encoding + both MLPs inside the fused
// kernel, with the weights staged in local memory, against the field's own kernels.
TEST(FusedMarcher, TrainedNerfMatchesWavefront) {
  using namespace lorgnette::nerf;
  cl::Runtime& rt = runtime();
  nerftest::SceneViews train = nerftest::render_views(nerftest::ring_cameras(12, 2.2f, 48));
  ModelSizing sizing = choose_model_size(train.views, SizingOverrides{});
  sizing.field.levels = 8;
  sizing.field.log2_table_size = 14;
  sizing.field.finest_resolution = 256;
  NerfModel model(rt, sizing.field, sizing.aabb, sizing.occupancy_resolution, sizing.step, 1u << 14, 5, true);
  TrainOptions to;
  to.steps = 40;
  to.seed = 5;
  to.progress = false;
  Trainer(model, train.views, to, sizing.occupancy_mask).run();

  const Camera cam = nerftest::ring_cameras(4, 2.2f, 40, 0.37f)[1];
  lorgnette::SurfaceBuffers surf(40, 40);  // a lens across the middle rows, half covering
  for (int y = 15; y < 25; ++y)
    for (int x = 0; x < 40; ++x) set_surface(surf, x, y, {0.1f, 0.1f, 0.6f}, (x % 4) ? 0.5f : 1.0f, 1.9f);
  Renderer renderer(rt);
  RenderOptions o;
  o.background = {0.9f, 0.3f, 0.6f};
  const lorgnette::SurfaceBuffers *none = nullptr, *lens = &surf;
  for (const lorgnette::SurfaceBuffers* s : {none, lens}) {
    RenderResult wave = renderer.render(model, cam, s, forced(MarcherKind::Wavefront, o));
    RenderResult fused = renderer.render(model, cam, s, forced(MarcherKind::Fused, o));
    Diff d = compare(wave, fused);
    uint32_t opaque = 0;
    for (int y = 0; y < 40; ++y)
      for (int x = 0; x < 40; ++x) opaque += wave.rgba.at(x, y, 3) > 0.5f;
    std::printf(
        "trained NeRF%s: %u opaque pixels, %.2f samples/ray, max |d rgba| %.3g, max d depth %.3g, "
        "sample-count mismatches %d\n",
        s ? " + lens" : "", opaque, fused.samples_per_ray(), d.rgba, d.depth, d.sample_mismatches);
    EXPECT_GT(opaque, 40u * 40u / 8) << "the view must show the sphere";
    EXPECT_LT(d.rgba, 1e-4);
    EXPECT_LT(d.depth, 1e-4);
    EXPECT_LE(d.sample_mismatches, 4);
  }

  // The variant for fields whose weights do not fit local memory reads them from global memory;
  // forced here through FusedMarcher itself, it must give the staged variant's image bit for bit.
  Renderer staged(rt);
  RenderResult ref = staged.render(model, cam, nullptr, forced(MarcherKind::Fused, o));
  NerfSource source(model.field());
  VolumeScene scene;
  scene.aabb_min = model.aabb().min;
  scene.aabb_max = model.aabb().max;
  scene.step = model.step();
  scene.occupancy = {LGN_MARCH_OCC_LINEAR, model.occupancy_resolution(), &model.occupancy_bits()};
  scene.field = &source;
  FusedMarcher global(rt, false);
  global.prepare(scene);
  EXPECT_FALSE(global.local_weights());
  EXPECT_NE(global.options().find("LGN_FUSED_LOCAL_WEIGHTS=0"), std::string::npos);
  const uint32_t pixels = cam.width * cam.height;
  cl::Buffer<float> none4(rt, 4), none3(rt, 3), none1(rt, 1), rgba(rt, 4 * pixels), depth(rt, pixels);
  cl::Buffer<uint32_t> samples(rt, pixels);
  rgba.fill(rt, 0.0f);
  depth.fill(rt, 0.0f);
  samples.fill(rt, 0u);
  MarchParams p{};  // as Marcher::render sets it for one pass at the pixel centres
  p.cam = cam;
  for (int a = 0; a < 3; ++a) {
    p.aabb_min[a] = scene.aabb_min[a];
    p.aabb_max[a] = scene.aabb_max[a];
    p.background[a] = o.background[a];
  }
  p.step = scene.step;
  p.min_transmittance = o.min_transmittance;
  p.sample_weight = 1.0f;
  p.jitter_u = p.jitter_v = 0.5f;
  p.occ_layout = LGN_MARCH_OCC_LINEAR;
  p.occ_res = model.occupancy_resolution();
  p.max_samples = 1u << 20;
  p.ray_count = pixels;
  global.march(p, {&model.occupancy_bits(), &none4, &none1, &none3, &rgba, &depth, &samples});
  std::vector<float> got = rgba.read(rt);
  int differ = 0;
  for (size_t i = 0; i < got.size(); ++i) differ += got[i] != ref.rgba.pixels[i];
  EXPECT_EQ(differ, 0) << "weights from global memory against weights staged in local memory";
}
