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

// The device way (sample_offsets' scan and fit on the device, one read of the batch record) writes
// exactly what the host way (counts read back, host prefix sum and fit) writes, and its loss and
// gradients equal the host render's: the same rays, offsets, samples, targets and gradients bit for
// bit; the loss sum (float on the device, double on the host) within 1e-5 relative.
TEST(Sampling, DeviceScanAndFitWriteWhatTheHostWayWrites) {
  Fixture f;
  auto scene = nerftest::render_views(nerftest::ring_cameras(3, 2.5f, 16));
  DeviceViews views(f.rt, scene.views, true);
  RayBatch batch(f.model, 4096);
  SampleParams p = sample_params_for(f.model, views);
  p.mode = SAMPLE_MODE_TRAIN;
  p.n_rays = 4096;
  p.seed = 3;
  p.iteration = 11;
  const uint32_t stride = f.model.field().max_batch();
  const std::vector<uint32_t> counts = batch.count(p, views);
  uint64_t counted = 0;
  for (uint32_t c : counts) counted += c;
  ASSERT_GT(counted, stride) << "the rays must overflow the batch, so the fit cuts them";
  const uint32_t end = batch.fit(0, stride);
  const uint32_t n = batch.write(p, views, 0, end);
  ASSERT_GT(end, 0u);
  ASSERT_LT(end, p.n_rays);
  auto read_all = [&] {
    return std::vector<std::vector<float>>{batch.positions().read(f.rt), batch.directions().read(f.rt),
                                           batch.ray_info().read(f.rt, size_t(end) * RAY_INFO_FLOATS)};
  };
  std::vector<std::vector<float>> host = read_all();
  // Field outputs for the loss: a fixed pseudo-random density and colour per sample.
  std::mt19937 gen(17);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> sigma(stride), rgb(3 * size_t(stride));
  for (float& v : sigma) v = 40.0f * u(gen);
  for (float& v : rgb) v = u(gen);
  batch.sigma().write(f.rt, sigma);
  batch.rgb().write(f.rt, rgb);
  const double host_loss = batch.render(LOSS_L2_SRGB, false);
  const std::vector<float> host_dsigma = batch.dsigma().read(f.rt), host_drgb = batch.drgb().read(f.rt);

  for (auto* b :
       {&batch.positions(), &batch.directions(), &batch.ray_info_mut(), &batch.dsigma(), &batch.drgb()})
    b->fill(f.rt, -1.0f);
  const RayBatch::DeviceBatch d = batch.sample_on_device(p, views);
  EXPECT_EQ(d.rays, end);
  EXPECT_EQ(d.samples, n);
  EXPECT_EQ(d.counted, counted);
  std::vector<std::vector<float>> dev = read_all();
  for (int a = 0; a < 3; ++a)
    for (uint32_t i = 0; i < n; ++i) {
      ASSERT_EQ(dev[0][a * size_t(stride) + i], host[0][a * size_t(stride) + i])
          << "position " << a << " " << i;
      ASSERT_EQ(dev[1][a * size_t(stride) + i], host[1][a * size_t(stride) + i])
          << "direction " << a << " " << i;
    }
  EXPECT_TRUE(dev[2] == host[2]) << "ray records";
  batch.render_on_device(LOSS_L2_SRGB);
  const float device_loss = batch.loss_sum();
  EXPECT_NEAR(device_loss, host_loss, 1e-5 * host_loss);
  const std::vector<float> dsigma = batch.dsigma().read(f.rt), drgb = batch.drgb().read(f.rt);
  for (uint32_t i = 0; i < n; ++i) ASSERT_EQ(dsigma[i], host_dsigma[i]) << "dsigma " << i;
  for (int c = 0; c < 3; ++c)
    for (uint32_t i = 0; i < n; ++i)
      ASSERT_EQ(drgb[c * size_t(stride) + i], host_drgb[c * size_t(stride) + i]);
  // The next step's read brings this loss along.
  p.iteration = 12;
  EXPECT_EQ(batch.sample_on_device(p, views).previous_loss_sum, device_loss);
}

// sample_offsets and loss_sum launched directly against a host prefix sum, fit and sum, for ray
// counts around the group size, zero counts, a budget hit exactly, and group sizes 1, 3 and 256.
TEST(Sampling, OffsetsScanAndLossSumMatchTheHostForAnyGroupSize) {
  cl::Runtime rt{cl::RuntimeOptions{"", "", false}};
  cl_program sampling = rt.program("train/sampling.cl"), loss = rt.program("train/loss.cl");
  cl::Kernel scan(sampling, "sample_offsets"), sum(loss, "loss_sum");
  std::mt19937 gen(23);
  for (uint32_t n_rays : {0u, 1u, 7u, 256u, 1000u, 3001u}) {
    std::vector<uint32_t> counts(std::max(n_rays, 1u));
    for (auto& c : counts) c = gen() % 4 == 0 ? 0u : gen() % 97;
    std::vector<uint32_t> offsets_ref(n_rays);
    uint32_t total = 0;
    for (uint32_t i = 0; i < n_rays; ++i) {
      offsets_ref[i] = total;
      total += counts[i];
    }
    // Budgets: none fit (below the first non-empty ray), exactly the inclusive sum of ray n/2, all.
    std::vector<uint32_t> budgets = {0u, total + 5u};
    if (n_rays > 1) budgets.push_back(offsets_ref[n_rays / 2] + counts[n_rays / 2]);
    for (uint32_t budget : budgets) {
      uint32_t fit = 0, fit_samples = 0;
      while (fit < n_rays && fit_samples + counts[fit] <= budget) fit_samples += counts[fit++];
      for (size_t group : {size_t(1), size_t(3), size_t(BATCH_SCAN_MAX_GROUP)}) {
        cl::Buffer<uint32_t> c_dev(rt, counts), off_dev(rt, counts.size()), info(rt, BATCH_INFO_UINTS);
        info.fill(rt, 0xdeadbeefu);
        SampleParams p{};
        p.n_rays = n_rays;
        p.stride = budget;
        scan.args(p, c_dev, off_dev, info).launch(rt, group, group);
        const std::vector<uint32_t> got = info.read(rt);
        const std::string what = "rays " + std::to_string(n_rays) + ", budget " + std::to_string(budget) +
                                 ", group " + std::to_string(group);
        EXPECT_EQ(got[BATCH_INFO_RAYS], fit) << what;
        EXPECT_EQ(got[BATCH_INFO_SAMPLES], fit_samples) << what;
        EXPECT_EQ(got[BATCH_INFO_COUNTED], total) << what;
        EXPECT_EQ(got[BATCH_INFO_LOSS], 0xdeadbeefu) << what << ": the scan must leave the loss alone";
        if (n_rays) {
          EXPECT_EQ(off_dev.read(rt, n_rays), offsets_ref) << what;
        }
      }
    }
    std::vector<float> losses(counts.size());
    double ref = 0.0;
    for (uint32_t i = 0; i < n_rays; ++i)
      ref += losses[i] = std::uniform_real_distribution<float>(0, 0.1f)(gen);
    cl::Buffer<float> l_dev(rt, losses);
    for (size_t group : {size_t(1), size_t(3), size_t(BATCH_SCAN_MAX_GROUP)}) {
      cl::Buffer<uint32_t> info(rt, BATCH_INFO_UINTS);
      LossParams lp{};
      lp.n_rays = n_rays;
      float bits[2];
      for (int run = 0; run < 2; ++run) {
        info.fill(rt, 0u);
        sum.args(lp, l_dev, info).launch(rt, group, group);
        uint32_t u = info.read(rt)[BATCH_INFO_LOSS];
        std::memcpy(&bits[run], &u, 4);
      }
      // n * 0.05 summed in float: rounding ~ n * 6e-8 of the sum at worst.
      EXPECT_NEAR(bits[0], ref, 1e-5 * ref + 1e-9) << n_rays << " rays, group " << group;
      EXPECT_EQ(std::memcmp(&bits[0], &bits[1], 4), 0) << "loss_sum is not reproducible";
    }
  }
}

}  // namespace
