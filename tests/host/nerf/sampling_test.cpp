// The training/eval ray sampler (kernels/train/sampling.cl via RayBatch) against a brute-force host
// reference on a hand-made occupancy grid: the reference walks every step of the sample lattice and
// keeps the positions in occupied cells, so it checks that skipping empty cells never drops or
// adds a sample. Also: training-mode rays are reproducible and their targets composite the alpha.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "host/nerf/ray_batch.h"
#include "kernels/train/occupancy.h"
#include "synthetic_scene.h"

namespace {

using namespace lorgnette;
using namespace lorgnette::nerf;

field::FieldConfig tiny_config() {
  field::FieldConfig c;
  c.log2_table_size = 10;
  c.finest_resolution = 32;
  return c;
}

struct Fixture {
  cl::Runtime rt{cl::RuntimeOptions{"", "", false}};
  NerfModel model{rt, tiny_config(), Aabb{{-1.0f, -0.8f, -1.2f}, {1.0f, 0.9f, 1.1f}}, 8, 0.02f, 1u << 14,
                  1,  true};
  Fixture() {
    OccupancyGrid g = full_occupancy(8);
    std::mt19937 gen(5);
    for (auto& w : g.bits) w &= gen() & gen();  // about a quarter of the cells occupied
    model.set_occupancy(g);
  }
};

// Host reference of one view-mode ray: every lattice point t_start + k*step inside the box, kept
// when its cell is occupied.
std::vector<std::array<float, 3>> reference_samples(const NerfModel& m, const Camera& cam, uint32_t pixel,
                                                    uint32_t max_samples) {
  float u = float(pixel % cam.width) + 0.5f, v = float(pixel / cam.width) + 0.5f;
  LgnVec3 o = camera_origin(&cam), d = camera_ray_dir(&cam, u, v);
  float oo[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z};
  float t0 = 0.0f, t1 = 3e38f;
  for (int a = 0; a < 3; ++a) {
    float ta = (m.aabb().min[a] - oo[a]) / dd[a], tb = (m.aabb().max[a] - oo[a]) / dd[a];
    t0 = std::max(t0, std::min(ta, tb));
    t1 = std::min(t1, std::max(ta, tb));
  }
  std::vector<std::array<float, 3>> out;
  if (!(t1 > t0)) return out;
  float t = t0 + 0.5f * m.step();
  for (; t < t1 && out.size() < max_samples; t += m.step()) {
    std::array<float, 3> q;
    for (int a = 0; a < 3; ++a) q[a] = (oo[a] + t * dd[a] - m.aabb().min[a]) / m.aabb().extent(a);
    if (occ_test(m.occupancy().bits.data(), m.occupancy().res, q[0], q[1], q[2])) out.push_back(q);
  }
  return out;
}

TEST(Sampling, ViewRaysMatchBruteForceReference) {
  Fixture f;
  Camera cam = nerftest::look_at_camera(2.2f, 1.3f, 2.7f, 24, 50.0f);
  DeviceViews views(f.rt, {View{cam, nullptr}}, false);
  RayBatch batch(f.model, 1024);
  SampleParams p = sample_params_for(f.model, views);
  p.mode = SAMPLE_MODE_VIEW;
  p.n_rays = cam.width * cam.height;
  std::vector<uint32_t> counts = batch.count(p, views);
  ASSERT_EQ(batch.fit(0, f.model.field().max_batch()), p.n_rays);
  uint32_t n = batch.write(p, views, 0, p.n_rays);
  std::vector<float> pos = batch.positions().read(f.rt);
  const uint32_t stride = f.model.field().max_batch();
  uint32_t offset = 0, mismatched = 0, total_ref = 0, nonempty = 0;
  for (uint32_t ray = 0; ray < p.n_rays; ++ray) {
    auto ref = reference_samples(f.model, cam, ray, p.max_samples);
    total_ref += ref.size();
    nonempty += !ref.empty();
    if (ref.size() != counts[ray]) {
      // A lattice point within float rounding of a cell face may land on either side.
      ++mismatched;
      offset += counts[ray];
      continue;
    }
    for (uint32_t k = 0; k < counts[ray]; ++k)
      for (int a = 0; a < 3; ++a)
        // Positions are o + t*d normalised, with t accumulated over up to ~200 steps in float32
        // on both sides (in a different order after a skip): 1e-4 of the unit box.
        ASSERT_NEAR(pos[a * stride + offset + k], ref[k][a], 1e-4f) << "ray " << ray << " sample " << k;
    offset += counts[ray];
  }
  EXPECT_EQ(offset, n);
  EXPECT_GT(nonempty, p.n_rays / 4);  // the test really exercises occupied and empty cells
  EXPECT_LE(mismatched, p.n_rays / 100) << "rays whose sample count differs from the reference";
  EXPECT_GT(total_ref, 1000u);
}

TEST(Sampling, SubRangesWriteTheSameSamples) {
  Fixture f;
  Camera cam = nerftest::look_at_camera(-2.0f, 0.5f, 2.5f, 16, 50.0f);
  DeviceViews views(f.rt, {View{cam, nullptr}}, false);
  RayBatch batch(f.model, 256);
  SampleParams p = sample_params_for(f.model, views);
  p.mode = SAMPLE_MODE_VIEW;
  p.n_rays = 256;
  batch.count(p, views);
  uint32_t n_all = batch.write(p, views, 0, 256);
  std::vector<float> all = batch.positions().read(f.rt, n_all);
  uint32_t end = batch.fit(100, n_all / 3);
  ASSERT_GT(end, 100u);
  uint32_t n_sub = batch.write(p, views, 100, end);
  std::vector<float> sub = batch.positions().read(f.rt, n_sub);
  uint32_t skip = 0;
  const auto& counts = batch.count(p, views);
  for (uint32_t r = 0; r < 100; ++r) skip += counts[r];
  for (uint32_t i = 0; i < n_sub; ++i) ASSERT_EQ(sub[i], all[skip + i]) << i;
}

TEST(Sampling, TrainingRaysAreReproducibleAndCompositeAlpha) {
  Fixture f;
  auto scene = nerftest::render_views(nerftest::ring_cameras(3, 2.5f, 16));
  DeviceViews views(f.rt, scene.views, true);
  RayBatch batch(f.model, 512);
  SampleParams p = sample_params_for(f.model, views);
  p.mode = SAMPLE_MODE_TRAIN;
  p.n_rays = 512;
  p.seed = 9;
  p.iteration = 4;
  std::vector<uint32_t> a = batch.count(p, views);
  std::vector<uint32_t> b = batch.count(p, views);
  EXPECT_EQ(a, b);
  p.iteration = 5;
  EXPECT_NE(batch.count(p, views), a);
  uint32_t end = batch.fit(0, f.model.field().max_batch());
  batch.write(p, views, 0, end);
  std::vector<float> info = batch.ray_info().read(f.rt, size_t(end) * RAY_INFO_FLOATS);
  int partial = 0;
  for (uint32_t r = 0; r < end; ++r) {
    const float* in = &info[r * RAY_INFO_FLOATS];
    uint32_t pixel, image;
    std::memcpy(&pixel, &in[6], 4);
    std::memcpy(&image, &in[7], 4);
    ASSERT_LT(image, 3u);
    ASSERT_LT(pixel, 16u * 16u);
    const Image& im = scene.images[image];
    float a = im.pixels[4 * pixel + 3];
    partial += a > 0.0f && a < 1.0f;
    for (int c = 0; c < 3; ++c) {
      EXPECT_GE(in[3 + c], 0.0f);
      EXPECT_LT(in[3 + c], 1.0f);
      EXPECT_NEAR(in[c], im.pixels[4 * pixel + c] * a + in[3 + c] * (1.0f - a), 1e-6f);
    }
  }
  EXPECT_GT(partial, 0);  // edge pixels with partial coverage were drawn
}

}  // namespace
