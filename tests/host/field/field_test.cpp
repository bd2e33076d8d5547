// The whole Field: forward and backward vs the double host reference (default-like and padded
// shapes), the backward vs finite differences of the device forward, inference vs training paths,
// determinism, and bad-input errors.
#include "host/field/field.h"

#include "field_test_util.h"
#include "host/cl/buffer.h"
#include "host/field/density_at.h"

using namespace lorgnette;
using namespace lorgnette::field;

namespace {

constexpr uint32_t kN = 300;

// A Field whose hash tables are random in [-0.5, 0.5] (the 1e-4 init would hide the encoding).
struct FieldSetup {
  explicit FieldSetup(const FieldConfig& cfg, KernelVariant variant = KernelVariant::Auto,
                      bool deterministic = true)
      : field(test::runtime(), cfg, kN, 42, deterministic, variant),
        s(test::random_samples(kN, field.max_batch(), 9)) {
    auto& rt = test::runtime();
    params = field.download_params();
    auto h = test::random_vector(field.layout().hash_count, 0.5f, 77);
    std::copy(h.begin(), h.end(), params.begin());
    field.upload_params(params);
    const size_t S = field.max_batch();
    pos = cl::Buffer<float>(rt, s.pos);
    dir = cl::Buffer<float>(rt, s.dir);
    sigma = cl::Buffer<float>(rt, S);
    rgb = cl::Buffer<float>(rt, 3 * S);
    a = test::random_vector(S, 1.0f, 5);
    b = test::random_vector(3 * S, 1.0f, 6);
  }
  // L = sum a sigma + b . rgb over the valid samples, from the device forward.
  double loss() {
    auto& rt = test::runtime();
    field.forward(pos, dir, kN, sigma, rgb, false);
    auto sg = sigma.read(rt), c = rgb.read(rt);
    double L = 0;
    for (uint32_t i = 0; i < kN; ++i) {
      L += double(a[i]) * sg[i];
      for (int k = 0; k < 3; ++k) L += double(b[k * field.max_batch() + i]) * c[k * field.max_batch() + i];
    }
    return L;
  }
  void forward_backward() {
    auto& rt = test::runtime();
    field.forward(pos, dir, kN, sigma, rgb, true);
    cl::Buffer<float> da(rt, a), db(rt, b);
    field.backward(da, db, kN);
  }
  Field field;
  ref::Samples s;
  std::vector<float> params, a, b;
  cl::Buffer<float> pos, dir, sigma, rgb;
};

void check_against_reference(const FieldConfig& cfg, KernelVariant variant = KernelVariant::Auto) {
  auto& rt = test::runtime();
  FieldSetup t(cfg, variant);
  t.forward_backward();
  const auto& lay = t.field.layout();
  ref::Forward f = ref::forward(lay, cfg, t.params, t.s);
  const size_t S = t.field.max_batch();
  auto sg = t.sigma.read(rt, kN);
  auto c = t.rgb.read(rt);
  std::vector<float> rgb3;
  for (int k = 0; k < 3; ++k) rgb3.insert(rgb3.end(), c.begin() + k * S, c.begin() + k * S + kN);
  // Float MLP of ~100 O(1) terms per output vs double: ~1e-6 relative, 1e-4 leaves margin
  // (sigma = exp(raw) turns an absolute raw error into a relative one).
  test::expect_close(sg, f.sigma, 1e-4, 1e-6, "sigma");
  test::expect_close(rgb3, f.rgb, 1e-4, 1e-6, "rgb");

  std::vector<double> dsig(t.a.begin(), t.a.begin() + kN);
  ref::Rows drgb(3 * kN);
  for (int k = 0; k < 3; ++k)
    for (uint32_t i = 0; i < kN; ++i) drgb[k * kN + i] = t.b[k * S + i];
  auto want = ref::backward(lay, cfg, t.params, t.s, f, dsig, drgb);
  auto got = t.field.download_gradients();
  // Sums of 300 samples in float, chunked: ~1e-5 of the largest gradient of a group.
  std::vector<double> wh(want.begin(), want.begin() + lay.hash_count);
  std::vector<float> gh(got.begin(), got.begin() + lay.hash_count);
  test::expect_close(gh, wh, 1e-3, 1e-5 * test::max_abs(wh), "hash gradients");
  std::vector<double> wm(want.begin() + lay.mlp_offset, want.end());
  std::vector<float> gm(got.begin() + lay.mlp_offset, got.end());
  test::expect_close(gm, wm, 1e-3, 1e-5 * test::max_abs(wm), "MLP gradients");
}

}  // namespace

TEST(Field, ForwardAndBackwardMatchReference) { check_against_reference(test::small_config()); }

TEST(Field, PaddedShapesMatchReference) { check_against_reference(test::odd_config()); }

// The GPU kernels (per-sample MLP chain, per-(sample, level) hash encoding) forced on PoCL, against
// the same double reference and tolerances: what an NVIDIA device runs is checked here too.
TEST(Field, GpuKernelsMatchReference) {
  check_against_reference(test::small_config(), KernelVariant::Gpu);
  check_against_reference(test::odd_config(), KernelVariant::Gpu);
}

TEST(Field, BackwardMatchesFiniteDifferencesOfTheDeviceForward) {
  for (KernelVariant v : {KernelVariant::Cpu, KernelVariant::Gpu}) {
    SCOPED_TRACE(v == KernelVariant::Gpu ? "gpu variant" : "cpu variant");
    FieldSetup t(test::small_config(), v);
    t.forward_backward();
    auto g = t.field.download_gradients();
    const auto& lay = t.field.layout();
    // The largest gradient of each group: a hash entry, density layers, colour layers.
    std::vector<std::pair<uint64_t, uint64_t>> groups = {{0, lay.hash_count}};
    groups.push_back({lay.density[0].offset, lay.density[0].offset + lay.density[0].count()});
    groups.push_back({lay.density[1].offset, lay.density[1].offset + lay.density[1].count()});
    for (const auto& L : lay.color) groups.push_back({L.offset, L.offset + L.count()});
    for (auto [begin, end] : groups) {
      uint64_t best = begin;
      for (uint64_t e = begin; e < end; ++e)
        if (std::fabs(g[e]) > std::fabs(g[best])) best = e;
      std::vector<float> p = t.params;
      const float step = 1e-2f;
      p[best] = t.params[best] + step;
      t.field.upload_params(p);
      const double Lp = t.loss();
      p[best] = t.params[best] - step;
      t.field.upload_params(p);
      const double Lm = t.loss();
      t.field.upload_params(t.params);
      const double fd = (Lp - Lm) / (2.0 * step);
      // Float forward noise (~1e-6 of L ~ 1e2) / 2e-2 and O(step^2) curvature: 3 % + 1e-2.
      EXPECT_NEAR(g[best], fd, 1e-2 + 3e-2 * std::fabs(fd)) << "parameter " << best;
    }
  }
}

// The GPU training path against the CPU path on the same parameters and samples: the GPU kernels
// (local-weights MLP chain, per-sample hash encoding) with the deterministic hash backward and with
// the compare-and-swap atomic one (what a GPU runs without --deterministic).
TEST(Field, GpuGradientsMatchTheCpuPath) {
  FieldSetup cpu(test::small_config(), KernelVariant::Cpu);
  cpu.forward_backward();
  const std::vector<float> want = cpu.field.download_gradients();
  const ParamLayout& lay = cpu.field.layout();
  const std::vector<double> wh(want.begin(), want.begin() + lay.hash_count);
  const std::vector<double> wm(want.begin() + lay.mlp_offset, want.end());
  for (bool deterministic : {true, false}) {
    SCOPED_TRACE(deterministic ? "deterministic" : "atomic hash backward");
    FieldSetup gpu(test::small_config(), KernelVariant::Gpu, deterministic);
    gpu.forward_backward();
    const std::vector<float> got = gpu.field.download_gradients();
    // Both float, different summation orders (float16 lanes vs per sample; atomics in any order):
    // ~1e-6 relative per sum of 300 samples; 1e-4 relative + 1e-6 of the group's largest.
    test::expect_close(std::vector<float>(got.begin(), got.begin() + lay.hash_count), wh, 1e-4,
                       1e-6 * test::max_abs(wh), "hash gradients");
    test::expect_close(std::vector<float>(got.begin() + lay.mlp_offset, got.end()), wm, 1e-4,
                       1e-6 * test::max_abs(wm), "MLP gradients");
  }
}

TEST(Field, DensityMatchesForwardSigma) {
  auto& rt = test::runtime();
  FieldSetup t(test::small_config());
  t.field.forward(t.pos, t.dir, kN, t.sigma, t.rgb, false);
  auto s1 = t.sigma.read(rt, kN);
  cl::Buffer<float> s2(rt, kN);
  t.field.density(t.pos, kN, s2);
  EXPECT_EQ(s1, s2.read(rt));
}

TEST(Field, SameSeedGivesBitwiseIdenticalTraining) {
  auto& rt = test::runtime();
  std::vector<std::vector<float>> results;
  for (uint64_t seed : {5, 5, 6}) {
    Field field(rt, test::small_config(), 1000, seed, true);
    ref::Samples s = test::random_samples(1000, field.max_batch(), 3);
    cl::Buffer<float> pos(rt, s.pos), dir(rt, s.dir), sigma(rt, field.max_batch()),
        rgb(rt, 3 * field.max_batch());
    cl::Buffer<float> da(rt, test::random_vector(field.max_batch(), 1.0f, 1));
    cl::Buffer<float> db(rt, test::random_vector(3 * field.max_batch(), 1.0f, 2));
    for (int step = 0; step < 3; ++step) {
      field.forward(pos, dir, 1000, sigma, rgb, true);
      field.backward(da, db, 1000);
      field.adam_step(AdamConfig{});
    }
    results.push_back(field.download_params());
  }
  EXPECT_TRUE(results[0] == results[1]) << "same seed, same device: parameters must be bitwise equal";
  EXPECT_FALSE(results[0] == results[2]) << "a different seed must give a different field";
}

// density_at takes host points through Field::density in batches of its capacity: 300 points over a
// 128-sample field (three launches, the last one partial) give the CPU reference's sigma at each
// point, in order.
TEST(Field, DensityAtHostPointsMatchesTheReference) {
  auto& rt = test::runtime();
  const FieldConfig cfg = test::small_config();
  Field field(rt, cfg, 100, 42, true);
  ASSERT_EQ(field.max_batch(), 128u);
  std::vector<float> params = field.download_params();
  const auto h = test::random_vector(field.layout().hash_count, 0.5f, 77);  // varied densities
  std::copy(h.begin(), h.end(), params.begin());
  field.upload_params(params);
  const ref::Samples s = test::random_samples(kN, kN, 9);
  std::vector<std::array<float, 3>> points(kN);
  for (uint32_t i = 0; i < kN; ++i)
    for (int a = 0; a < 3; ++a) points[i][size_t(a)] = s.pos[size_t(a) * kN + i];
  const std::vector<float> got = density_at(field, rt, points);
  const ref::Forward want = ref::forward(field.layout(), cfg, params, s);
  test::expect_close(got, want.sigma, 1e-4, 1e-6, "sigma");  // tolerances as in check_against_reference
  // The densities differ from point to point far beyond the tolerance, so a point out of order shows.
  EXPECT_GT(*std::max_element(got.begin(), got.end()) - *std::min_element(got.begin(), got.end()), 0.1f);
  EXPECT_TRUE(density_at(field, rt, {}).empty());
}

TEST(Field, BadUseIsAClearError) {
  auto& rt = test::runtime();
  Field field(rt, test::small_config(), 100, 1, true);
  EXPECT_EQ(field.max_batch(), 128u);
  cl::Buffer<float> pos(rt, 3 * 128), dir(rt, 3 * 128), sigma(rt, 128), rgb(rt, 3 * 128), small(rt, 10);
  pos.fill(rt, 0.5f);
  dir.fill(rt, 0.0f);
  EXPECT_THROW(field.backward(sigma, rgb, 10), std::logic_error);  // no forward yet
  EXPECT_THROW(field.forward(pos, dir, 129, sigma, rgb, true), std::invalid_argument);
  EXPECT_THROW(field.forward(small, dir, 10, sigma, rgb, true), std::invalid_argument);
  field.forward(pos, dir, 10, sigma, rgb, true);
  EXPECT_THROW(field.backward(sigma, rgb, 11), std::logic_error);  // n differs
  EXPECT_THROW(field.upload_params(std::vector<float>(5)), std::invalid_argument);
  EXPECT_THROW(Field(rt, test::small_config(), 0, 1, true), std::invalid_argument);
}

TEST(Field, UploadResetsTheOptimiser) {
  auto& rt = test::runtime();
  std::vector<std::vector<float>> results;
  for (int warm_steps : {2, 0}) {
    Field field(rt, test::small_config(), 256, 8, true);
    const std::vector<float> p0 = field.download_params();
    ref::Samples s = test::random_samples(256, field.max_batch(), 4);
    cl::Buffer<float> pos(rt, s.pos), dir(rt, s.dir), sigma(rt, 256), rgb(rt, 3 * 256);
    cl::Buffer<float> da(rt, test::random_vector(256, 1.0f, 1)),
        db(rt, test::random_vector(3 * 256, 1.0f, 2));
    auto step = [&] {
      field.forward(pos, dir, 256, sigma, rgb, true);
      field.backward(da, db, 256);
      field.adam_step(AdamConfig{});
    };
    for (int k = 0; k < warm_steps; ++k) step();
    field.upload_params(p0);
    EXPECT_EQ(field.adam_steps(), 0u);
    step();
    results.push_back(field.download_params());
  }
  EXPECT_TRUE(results[0] == results[1]) << "Adam moments must not survive upload_params";
}

// Adam clears the hash gradients it has used, so the next backward accumulates into zeros without
// a clearing pass of its own: its gradients must equal those of a backward that starts from a
// freshly cleared buffer (upload_params) at the same parameters, on both kernel variants.
TEST(Field, BackwardAfterAnAdamStepEqualsAFreshBackward) {
  for (KernelVariant v : {KernelVariant::Cpu, KernelVariant::Gpu}) {
    FieldSetup t(test::small_config(), v);
    t.forward_backward();
    t.field.adam_step(AdamConfig{});
    const std::vector<float> stepped = t.field.download_params();
    t.forward_backward();
    const std::vector<float> after_adam = t.field.download_gradients();
    t.field.upload_params(stepped);
    t.forward_backward();
    EXPECT_TRUE(after_adam == t.field.download_gradients())
        << (v == KernelVariant::Gpu ? "gpu" : "cpu") << " variant: stale gradients after adam_step";
  }
}
