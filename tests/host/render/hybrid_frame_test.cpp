// The hybrid frame (host/render/hybrid_frame) on PoCL: the surface pass overlapped with the march
// must give the image of the sequential frame (surface pass, then march) bit for bit, since every
// pixel still composites its own segments and passes in the same order; the overlap must be real
// (the march evaluates the field before the surface pass returns); glasses out of view cost no
// surface pass; failures on either side reach the caller. The scene is an analytic sphere in a
// haze (exact, cheap) with a small field batch so the frame takes several tiles; the "glasses" are
// surface buffers written by hand inside a rectangle (depths inside the volume, partial coverage,
// a tint), as the surface pass fills them.
#include "host/render/hybrid_frame.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <thread>

#include "host/render/analytic_field.h"
#include "host/render/orbit.h"

using namespace lorgnette;
using namespace lorgnette::render;

namespace {
cl::Runtime& runtime() {
  static cl::Runtime rt;
  return rt;
}

// The analytic field, counting the samples it evaluates (to see the march run).
class CountingField : public RadianceSource {
 public:
  CountingField()
      : field_(runtime(), {-1, -1, -1}, {1, 1, 1},
               {analytic_box({-2, -2, -2}, {2, 2, 2}, 0.3f, {0.4f, 0.5f, 0.6f}),
                analytic_sphere({0.1f, 0.0f, 0.0f}, 0.6f, 8.0f, {0.9f, 0.6f, 0.4f})},
               4096) {}
  uint32_t max_batch() const override { return field_.max_batch(); }
  void evaluate(const cl::Buffer<float>& pos, const cl::Buffer<float>& dir, uint32_t n,
                cl::Buffer<float>& sigma, cl::Buffer<float>& rgb) override {
    field_.evaluate(pos, dir, n, sigma, rgb);
    evaluated += n;
  }
  std::atomic<uint64_t> evaluated{0};

 private:
  AnalyticField field_;
};

constexpr uint32_t kW = 64, kH = 40;
const std::array<uint32_t, 4> kRect{12, 14, 50, 23};  // the glasses' rows are 14..22

struct Scene {
  CountingField field;
  VolumeScene scene;
  Camera cam = look_at({0.4f, 0.3f, 3.0f}, {0, 0, 0}, {0, 1, 0}, kW, kH, 35.0f);
  Scene() {
    scene.aabb_min = {-1, -1, -1};
    scene.aabb_max = {1, 1, 1};
    scene.step = 0.011f;
    scene.field = &field;
  }
};

// Hand-made surface buffers: inside kRect a pattern of opaque, half-covering and tinted pixels at
// depths in front of, inside and behind the sphere; nothing outside.
lorgnette::SurfaceBuffers hand_surfaces(const Camera& cam) {
  lorgnette::SurfaceBuffers s(int(cam.width), int(cam.height));
  for (uint32_t y = kRect[1]; y < kRect[3]; ++y)
    for (uint32_t x = kRect[0]; x < kRect[2]; ++x) {
      size_t i = size_t(y) * cam.width + x;
      float a = (x + y) % 3 == 0 ? 1.0f : 0.35f + 0.02f * float(x % 7);
      float c[3] = {0.2f + 0.01f * x, 0.5f, 0.8f - 0.02f * y};
      for (int k = 0; k < 3; ++k) s.color_alpha[4 * i + k] = a * c[k];
      s.color_alpha[4 * i + 3] = a;
      s.depth[i] = 2.2f + 0.027f * float(x) + 0.013f * float(y);
      s.filter[3 * i + 0] = 1.2f, s.filter[3 * i + 1] = 1.0f, s.filter[3 * i + 2] = 0.8f;
    }
  return s;
}

GlassesSurfaces hand_glasses(std::function<void()> during_pass = {}) {
  GlassesSurfaces g;
  g.screen_rect = [](const Camera&) { return kRect; };
  g.render = [during_pass](const Camera& cam, uint32_t) {
    if (during_pass) during_pass();
    return hand_surfaces(cam);
  };
  return g;
}

void expect_same_image(const RenderResult& a, const RenderResult& b) {
  ASSERT_EQ(a.rgba.pixels.size(), b.rgba.pixels.size());
  EXPECT_EQ(0, std::memcmp(a.rgba.pixels.data(), b.rgba.pixels.data(), 4 * a.rgba.pixels.size()));
  EXPECT_EQ(0, std::memcmp(a.depth.pixels.data(), b.depth.pixels.data(), 4 * a.depth.pixels.size()));
  EXPECT_EQ(a.samples.pixels, b.samples.pixels);
  EXPECT_EQ(a.samples_composited, b.samples_composited);
}
}  // namespace

TEST(HybridFrame, ConcurrentEqualsSequentialBitForBit) {
  Scene s;
  Marcher m(runtime());
  GlassesSurfaces g = hand_glasses();
  for (uint32_t spp : {1u, 3u}) {
    FrameOptions o;
    o.march.spp = spp;
    o.concurrent = false;
    RenderResult seq = render_hybrid_frame(m, s.scene, s.cam, &g, o);
    o.concurrent = true;
    RenderResult con = render_hybrid_frame(m, s.scene, s.cam, &g, o);
    expect_same_image(seq, con);
    // ... and both equal the marcher given the whole buffers up front.
    lorgnette::SurfaceBuffers whole = hand_surfaces(s.cam);
    expect_same_image(seq, m.render(s.scene, s.cam, &whole, o.march));
    // The glasses change the band's pixels (so the comparison above covers them) and no others.
    RenderResult head = m.render(s.scene, s.cam, nullptr, o.march);
    int changed_in = 0, changed_out = 0;
    for (uint32_t y = 0; y < kH; ++y)
      for (uint32_t x = 0; x < kW; ++x) {
        bool in = x >= kRect[0] && x < kRect[2] && y >= kRect[1] && y < kRect[3];
        bool changed = con.rgba.at(int(x), int(y), 0) != head.rgba.at(int(x), int(y), 0);
        (in ? changed_in : changed_out) += changed;
      }
    EXPECT_GT(changed_in, int((kRect[2] - kRect[0]) * (kRect[3] - kRect[1]) / 2));
    EXPECT_EQ(changed_out, 0);
  }
}

// The march of the rows outside the band runs while the surface pass does: the pass waits (up to
// 30 s) for the field to have been evaluated. Sequentially it must see no evaluation at all.
TEST(HybridFrame, MarchRunsWhileTheSurfacePassDoes) {
  Scene s;
  Marcher m(runtime());
  uint64_t seen = 0;
  GlassesSurfaces g = hand_glasses([&] {
    auto t0 = std::chrono::steady_clock::now();
    while (s.field.evaluated.load() == 0 && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(30))
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    seen = s.field.evaluated.load();
  });
  FrameOptions o;
  RenderResult con = render_hybrid_frame(m, s.scene, s.cam, &g, o);
  EXPECT_GT(seen, 0u) << "the march waited for the surface pass before marching";
  EXPECT_LT(seen, con.samples_evaluated) << "the band must be marched after the surface pass";
  EXPECT_GT(con.times.surface, 0.0);

  s.field.evaluated = 0;
  GlassesSurfaces first = hand_glasses([&] { seen = s.field.evaluated.load(); });
  o.concurrent = false;
  render_hybrid_frame(m, s.scene, s.cam, &first, o);
  EXPECT_EQ(seen, 0u);
}

TEST(HybridFrame, GlassesOutOfViewRunNoSurfacePass) {
  Scene s;
  Marcher m(runtime());
  int passes = 0;
  GlassesSurfaces g;
  g.screen_rect = [](const Camera& cam) {
    return std::array<uint32_t, 4>{0, cam.height, cam.width, cam.height};
  };
  g.render = [&](const Camera& cam, uint32_t) {
    ++passes;
    return lorgnette::SurfaceBuffers(int(cam.width), int(cam.height));
  };
  RenderResult r = render_hybrid_frame(m, s.scene, s.cam, &g, FrameOptions{});
  EXPECT_EQ(passes, 0);
  expect_same_image(r, m.render(s.scene, s.cam, nullptr, RenderOptions{}));
}

TEST(HybridFrame, FailuresReachTheCaller) {
  Scene s;
  Marcher m(runtime());
  GlassesSurfaces g = hand_glasses([] { throw std::runtime_error("surface pass failed"); });
  EXPECT_THROW(render_hybrid_frame(m, s.scene, s.cam, &g, FrameOptions{}), std::runtime_error);
  GlassesSurfaces wrong;  // buffers of the wrong size: the marcher says so once they arrive
  wrong.screen_rect = [](const Camera&) { return kRect; };
  wrong.render = [](const Camera&, uint32_t) { return lorgnette::SurfaceBuffers(8, 8); };
  EXPECT_THROW(render_hybrid_frame(m, s.scene, s.cam, &wrong, FrameOptions{}), std::invalid_argument);
  FrameOptions bad;
  bad.surface_spp = 0;
  GlassesSurfaces ok = hand_glasses();
  EXPECT_THROW(render_hybrid_frame(m, s.scene, s.cam, &ok, bad), std::invalid_argument);
  // The marcher is still usable after the failures.
  RenderResult r = render_hybrid_frame(m, s.scene, s.cam, &ok, FrameOptions{});
  EXPECT_GT(r.samples_composited, 0u);
}
