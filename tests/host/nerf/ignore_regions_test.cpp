// Training that leaves the views' ignore regions out (host/nerf/kept_pixels.h, View::ignore):
// - the rasterised spans match a brute-force point-in-polygon test on every pixel centre, and the
//   kept runs enumerate exactly the kept pixels in order;
// - the training sampler (kernels/train/sampling.cl) draws the pixel the host reference draws (the
//   shared hash, then the k-th kept pixel), never an ignored one, and without regions draws what it
//   drew before (the kept index is the pixel);
// - on the analytic sphere, a red blob painted over the sphere in one training view (a transient
//   occluder: a held card) is not learnt when that view's ignore region covers it, and is learnt
//   without the region: the render from that view's camera matches the clean sphere in the blob.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "host/nerf/kept_pixels.h"
#include "host/nerf/ray_batch.h"
#include "host/nerf/sizing.h"
#include "host/nerf/trainer.h"
#include "host/render/renderer.h"
#include "synthetic_scene.h"

namespace {

using namespace lorgnette;
using namespace lorgnette::nerf;

bool inside(const IgnorePolygon& p, float x, float y) {
  bool in = false;
  for (size_t i = 0; i < p.size(); ++i) {
    const auto &a = p[i], &b = p[(i + 1) % p.size()];
    if ((a.y() <= y) != (b.y() <= y) && x < a.x() + (y - a.y()) * (b.x() - a.x()) / (b.y() - a.y())) in = !in;
  }
  return in;
}

// Per pixel of a w x h image: ignored by the brute-force rule (centre inside any polygon).
std::vector<bool> brute_mask(const std::vector<IgnorePolygon>& polys, int w, int h) {
  std::vector<bool> m(size_t(w) * h, false);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (const auto& p : polys)
        m[size_t(y) * w + x] = m[size_t(y) * w + x] || inside(p, x + 0.5f, y + 0.5f);
  return m;
}

// Random quads (convex or not), a concave arrow, overlapping polygons and some reaching outside.
std::vector<IgnorePolygon> random_polygons(std::mt19937& gen, int w, int h) {
  std::uniform_real_distribution<float> ux(-8.0f, float(w) + 8.0f), uy(-8.0f, float(h) + 8.0f);
  std::vector<IgnorePolygon> polys;
  for (int k = 0; k < 3; ++k) {
    IgnorePolygon p;
    for (int v = 0; v < 4 + k; ++v) p.emplace_back(ux(gen), uy(gen));
    polys.push_back(p);
  }
  polys.push_back({{5.25f, 5.5f}, {20.0f, 12.0f}, {5.0f, 20.0f}, {10.0f, 12.5f}});  // concave arrow
  return polys;
}

TEST(KeptPixels, SpansAndRunsMatchBruteForce) {
  std::mt19937 gen(11);
  const std::vector<std::pair<int, int>> sizes = {{37, 23}, {16, 16}, {29, 31}, {40, 8}};
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<std::vector<IgnorePolygon>> polys(sizes.size());
    std::vector<const std::vector<IgnorePolygon>*> ignore(sizes.size(), nullptr);
    std::vector<uint32_t> kept_ref;  // global pixels kept, in order
    uint32_t base = 0;
    for (size_t v = 0; v < sizes.size(); ++v) {
      const auto [w, h] = sizes[v];
      if ((trial + v) % 3 != 0) polys[v] = random_polygons(gen, w, h), ignore[v] = &polys[v];
      const std::vector<bool> ref = brute_mask(polys[v], w, h);
      const auto spans = ignored_spans(polys[v], w, h);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          bool in_span = false;
          for (const auto& [x0, x1] : spans[size_t(y)]) in_span = in_span || (x >= x0 && x < x1);
          ASSERT_EQ(in_span, bool(ref[size_t(y) * w + x]))
              << "trial " << trial << " view " << v << " px " << x << "," << y;
          if (!ref[size_t(y) * w + x]) kept_ref.push_back(base + uint32_t(y * w + x));
        }
      base += uint32_t(w * h);
    }
    const KeptPixels k = kept_pixel_runs(sizes, ignore);
    ASSERT_EQ(k.kept, kept_ref.size());
    ASSERT_EQ(k.kept + k.ignored, base);
    for (uint32_t i = 0; i < k.kept; ++i) {  // the sampler's mapping, run by run
      size_t r = 0;
      while (r + 1 < k.runs.size() / 2 && k.runs[2 * (r + 1)] <= i) ++r;
      ASSERT_EQ(k.runs[2 * r + 1] + (i - k.runs[2 * r]), kept_ref[i]) << "kept index " << i;
    }
  }
  EXPECT_TRUE(kept_pixel_runs(sizes, {}).runs.empty());  // nothing ignored: no table
  std::vector<IgnorePolygon> all = {{{-1, -1}, {50, -1}, {50, 50}, {-1, 50}}};
  EXPECT_THROW(kept_pixel_runs({{16, 16}}, {&all}), std::runtime_error);
}

field::FieldConfig tiny_config() {
  field::FieldConfig c;
  c.log2_table_size = 10;
  c.finest_resolution = 32;
  return c;
}

// Training-mode rays: the image and pixel each ray reads (ray_info) against the host reference.
TEST(KeptPixels, TheSamplerDrawsOnlyKeptPixelsAsTheHostDoes) {
  cl::Runtime rt{cl::RuntimeOptions{"", "", false}};
  NerfModel model{rt, tiny_config(), Aabb{{-1, -1, -1}, {1, 1, 1}}, 8, 0.02f, 1u << 14, 1, true};
  OccupancyGrid empty = full_occupancy(8);  // no samples: only the rays' pixels are looked at
  for (auto& w : empty.bits) w = 0;
  model.set_occupancy(empty);
  nerftest::SceneViews s = nerftest::render_views(nerftest::ring_cameras(3, 2.2f, 24));
  const std::vector<IgnorePolygon> region = {{{3.5f, 2.0f}, {20.0f, 6.0f}, {14.0f, 21.5f}, {2.0f, 15.0f}}};
  for (bool with_region : {false, true}) {
    std::vector<View> views = s.views;
    if (with_region) views[1].ignore = &region;
    DeviceViews dv(rt, views, true);
    std::vector<bool> ignored(size_t(dv.total_pixels()), false);
    const std::vector<bool> m = brute_mask(region, 24, 24);
    if (with_region)
      for (size_t p = 0; p < m.size(); ++p) ignored[576 + p] = m[p];
    std::vector<uint32_t> kept;
    for (uint32_t p = 0; p < ignored.size(); ++p)
      if (!ignored[p]) kept.push_back(p);
    ASSERT_EQ(dv.sampled_pixels(), kept.size());
    RayBatch batch(model, 2048);
    SampleParams p = sample_params_for(model, dv);
    p.mode = SAMPLE_MODE_TRAIN;
    p.n_rays = 2048;
    p.seed = 5;
    p.iteration = 3;
    batch.count(p, dv);
    batch.write(p, dv, 0, p.n_rays);
    const std::vector<float> info = batch.ray_info().read(rt, size_t(p.n_rays) * RAY_INFO_FLOATS);
    for (uint32_t r = 0; r < p.n_rays; ++r) {
      uint32_t pixel, image;
      std::memcpy(&pixel, &info[r * RAY_INFO_FLOATS + 6], 4);
      std::memcpy(&image, &info[r * RAY_INFO_FLOATS + 7], 4);
      const uint32_t h = lgn_hash3(p.seed, p.iteration, r * 8u);
      const uint32_t want = kept[uint32_t((uint64_t(h) * kept.size()) >> 32)];
      ASSERT_EQ(image * 576 + pixel, want)
          << "ray " << r << (with_region ? " with" : " without") << " the region";
      ASSERT_FALSE(ignored[want]);
    }
  }
}

// The sphere's 16 ring views at 48 px, a red disc of radius 6 px over the sphere's centre in view 0.
struct BlobScene {
  static constexpr int kSize = 48, kCx = 24, kCy = 24, kR = 6;
  nerftest::SceneViews clean = nerftest::render_views(nerftest::ring_cameras(16, 2.2f, kSize));
  std::vector<Image> images = clean.images;
  std::vector<View> views = clean.views;
  std::vector<IgnorePolygon> region = {{{kCx - kR - 2.0f, kCy - kR - 2.0f},
                                        {kCx + kR + 2.0f, kCy - kR - 2.0f},
                                        {kCx + kR + 2.0f, kCy + kR + 2.0f},
                                        {kCx - kR - 2.0f, kCy + kR + 2.0f}}};
  BlobScene() {
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x)
        if ((x - kCx) * (x - kCx) + (y - kCy) * (y - kCy) <= kR * kR)
          for (int c = 0; c < 4; ++c) images[0].at(x, y, c) = c == 0 || c == 3 ? 1.0f : 0.0f;
    for (size_t i = 0; i < views.size(); ++i) views[i].image = &images[i];
  }
  bool in_blob(int x, int y) const { return (x - kCx) * (x - kCx) + (y - kCy) * (y - kCy) <= kR * kR; }
};

// Mean absolute error (linear RGB over white) inside the blob, of the model rendered from view 0's
// camera against the clean sphere.
double blob_error(NerfModel& model, const BlobScene& s) {
  render::RenderOptions ro;
  ro.background = {1.0f, 1.0f, 1.0f};
  const Image pred = render::render(model, s.views[0].camera, nullptr, ro).rgba;
  const Image& truth = s.clean.images[0];
  double sum = 0;
  int n = 0;
  for (int y = 0; y < BlobScene::kSize; ++y)
    for (int x = 0; x < BlobScene::kSize; ++x)
      if (s.in_blob(x, y))
        for (int c = 0; c < 3; ++c, ++n) {
          const float a = truth.at(x, y, 3), t = truth.at(x, y, c) * a + (1.0f - a);
          sum += std::abs(pred.at(x, y, c) - t);
        }
  return sum / n;
}

TEST(KeptPixels, ATransientInsideTheIgnoreRegionIsNotLearnt) {
  cl::Runtime rt{cl::RuntimeOptions{"", "", false}};
  BlobScene s;
  const ModelSizing sizing = choose_model_size(s.clean.views, SizingOverrides{});
  double err[2];
  for (int with_region = 0; with_region < 2; ++with_region) {
    std::vector<View> views = s.views;
    if (with_region) views[0].ignore = &s.region;
    NerfModel model(rt, sizing.field, sizing.aabb, sizing.occupancy_resolution, sizing.step, 1u << 13, 3,
                    true);
    TrainOptions o;
    o.steps = 250;
    o.seed = 3;
    o.progress = false;
    Trainer(model, views, o, sizing.occupancy_mask).run();
    err[with_region] = blob_error(model, s);
  }
  std::printf("mean |error| in the blob from its view: %.4f without the region, %.4f with it\n", err[0],
              err[1]);
  // The sphere is learnt to about 0.02 mean error per channel at this budget (~30 dB); the red blob
  // differs from the sphere there by ~0.45 per channel. Learnt, it leaves at least a quarter of that.
  EXPECT_LT(err[1], 0.05);
  EXPECT_GT(err[0], 0.10);
}

}  // namespace
