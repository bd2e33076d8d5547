// Volume rendering and loss (kernels/train/render.h, loss.cl): the constant-density slab against
// its closed form, the gradients against central finite differences, and the kernel against the
// host build of the same header.
#include "kernels/train/render.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "host/cl/kernel.h"
#include "host/cl/runtime.h"
#include "kernels/train/occupancy.h"

namespace {

using lorgnette::cl::Buffer;
using lorgnette::cl::Kernel;
using lorgnette::cl::Runtime;

struct Rays {
  std::vector<uint32_t> offsets, counts;
  std::vector<float> info, sigma, rgb, pos;  // rgb and pos (normalised to the box) SoA with stride
  uint32_t stride = 0;
};

Rays random_rays(uint32_t n_rays, uint32_t seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Rays r;
  uint32_t total = 0;
  for (uint32_t i = 0; i < n_rays; ++i) {
    r.offsets.push_back(total);
    r.counts.push_back(i % 7 == 0 ? 0 : 1 + gen() % 40);
    total += r.counts.back();
    for (int k = 0; k < int(RAY_INFO_FLOATS); ++k) r.info.push_back(u(gen));
  }
  r.stride = total + 5;
  r.sigma.resize(r.stride);
  r.rgb.resize(3 * r.stride);
  for (auto& s : r.sigma) s = 30.0f * u(gen) * u(gen);
  for (auto& c : r.rgb) c = u(gen);
  r.pos.resize(3 * r.stride);
  for (auto& x : r.pos) x = u(gen);
  return r;
}

// Runs render_loss on the device; returns colours (4/ray), losses, dsigma, drgb.
struct Out {
  std::vector<float> color, loss, dsigma, drgb;
};
Out run_kernel(Runtime& rt, const Rays& r, float step, uint32_t loss_kind, uint32_t forward_only,
               float opacity_prior = 0.0f, float room_clear = 0.0f, float room_clear_tolerance = 0.0f,
               const std::vector<uint32_t>& zones = {}, uint32_t zone_res = 0, float lean_gate = 0.0f,
               const std::vector<float>& skin_chroma = {}, float skin_tolerance = 0.0f) {
  uint32_t n = uint32_t(r.counts.size());
  Buffer<uint32_t> off(rt, r.offsets), cnt(rt, r.counts);
  Buffer<uint32_t> zone_bits(rt, zones.empty() ? std::vector<uint32_t>{0u} : zones);
  Buffer<float> info(rt, r.info), sigma(rt, r.sigma), rgb(rt, r.rgb), pos(rt, r.pos);
  Buffer<float> dsigma(rt, r.stride), drgb(rt, 3 * r.stride), loss(rt, n), color(rt, 4 * n);
  LossParams p{};
  p.n_rays = n, p.stride = r.stride, p.forward_only = forward_only, p.loss_kind = loss_kind;
  p.step = step, p.grad_scale = 1.0f / (3.0f * n), p.min_transmittance = 1e-4f;
  p.opacity_prior = opacity_prior, p.room_clear = room_clear, p.room_clear_tolerance = room_clear_tolerance;
  p.zone_res = zones.empty() ? 0u : zone_res;
  p.lean_gate = lean_gate;
  p.skin_count = uint32_t(skin_chroma.size() / 2), p.skin_tolerance = skin_tolerance;
  for (size_t i = 0; i < skin_chroma.size(); ++i) p.skin_chroma[i] = skin_chroma[i];
  Kernel k(rt.program("train/loss.cl"), "render_loss");
  k.args(p, off, cnt, info, sigma, rgb, dsigma, drgb, loss, color, pos, zone_bits).launch(rt, n, 64);
  return {color.read(rt), loss.read(rt), dsigma.read(rt), drgb.read(rt)};
}

TEST(Render, ConstantSlabMatchesClosedForm) {
  // N samples of density sigma, spacing step: T = exp(-sigma * N * step) exactly (product of
  // per-sample transmittances), C = c * (1 - T) + bg * T.
  Runtime rt({"", "", false});
  const float step = 0.01f, sigma = 7.5f;
  const uint32_t N = 50;  // slab thickness d = 0.5 -> T = exp(-3.75) = 0.0235
  Rays r;
  r.offsets = {0};
  r.counts = {N};
  r.info = {0, 0, 0, 0.2f, 0.4f, 0.6f, 0, 0, 0};
  r.stride = N;
  r.sigma.assign(N, sigma);
  r.rgb.clear();
  for (int c = 0; c < 3; ++c) r.rgb.insert(r.rgb.end(), N, 0.9f - 0.3f * c);
  Out o = run_kernel(rt, r, step, LOSS_L2_SRGB, 1);
  double T = std::exp(-double(sigma) * N * step);
  // float32 accumulation over 50 samples: relative error ~ 50 * 6e-8; 1e-5 leaves margin.
  EXPECT_NEAR(o.color[3], 1.0 - T, 1e-5);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(o.color[c], (0.9 - 0.3 * c) * (1.0 - T) + r.info[3 + c] * T, 1e-5);
}

// The host build of one ray: forward, the loss (its gradient scaled by grad_scale) and, when dsigma
// and drgb are given, the backward pass into them.
struct HostRay {
  float color[4];
  float loss;
  uint32_t used;
};
HostRay host_ray(const Rays& r, uint32_t ray, float step, uint32_t kind, float grad_scale,
                 std::vector<float>* dsigma = nullptr, std::vector<float>* drgb = nullptr) {
  HostRay h;
  float dC[3];
  const float* info = &r.info[RAY_INFO_FLOATS * ray];
  h.used = render_ray_forward(r.sigma.data(), r.rgb.data(), r.stride, r.offsets[ray], r.counts[ray], step,
                              1e-4f, info + 3, h.color);
  h.loss = render_ray_loss(h.color, info, kind, grad_scale, dC);
  if (dsigma && drgb)
    render_ray_backward(r.sigma.data(), r.rgb.data(), r.stride, r.offsets[ray], r.counts[ray], h.used, step,
                        h.color, dC, dsigma->data(), drgb->data());
  return h;
}

double host_loss(const Rays& r, uint32_t ray, float step, uint32_t kind) {
  return host_ray(r, ray, step, kind, 1.0f).loss;
}

TEST(Render, GradientsMatchFiniteDifferences) {
  Rays r = random_rays(8, 7);
  const float step = 0.02f;
  for (uint32_t kind : {LOSS_L2_SRGB, LOSS_L2_LINEAR}) {
    for (uint32_t ray = 1; ray < 8; ++ray) {
      uint32_t first = r.offsets[ray], count = r.counts[ray];
      std::vector<float> dsigma(r.stride), drgb(3 * r.stride);
      host_ray(r, ray, step, kind, 1.0f, &dsigma, &drgb);
      for (uint32_t k = 0; k < count; ++k) {
        uint32_t i = first + k;
        // Central differences in float32: eps 1e-2 on sigma (values up to 30) and 1e-3 on colours keeps
        // the truncation error ~eps^2 and the rounding error ~1e-7/eps well below the tolerance
        // of 1e-4 absolute + 1 % relative.
        auto fd = [&](float& x, float eps) {
          float save = x;
          x = save + eps;
          double lp = host_loss(r, ray, step, kind);
          x = save - eps;
          double lm = host_loss(r, ray, step, kind);
          x = save;
          return (lp - lm) / (2.0 * eps);
        };
        double g = fd(r.sigma[i], 1e-2f);
        EXPECT_NEAR(dsigma[i], g, 1e-4 + 0.01 * std::fabs(g)) << "ray " << ray << " sample " << k;
        for (int c = 0; c < 3; ++c) {
          double gc = fd(r.rgb[c * r.stride + i], 1e-3f);
          EXPECT_NEAR(drgb[c * r.stride + i], gc, 1e-4 + 0.01 * std::fabs(gc)) << "ray " << ray << " c " << c;
        }
      }
    }
  }
}

// The opacity prior (weight * ((1 - g) a (1 - a) + clear g a) per ray; g = 0: the binary prior
// alone): its gradient, added to the colour loss's, against central differences of the sum of both
// at several gates; the room gate against its closed form; and the kernel with the prior on against
// the host.
double host_loss_with_prior(const Rays& r, uint32_t ray, float step, float weight, float clear, float gate) {
  const HostRay h = host_ray(r, ray, step, LOSS_L2_SRGB, 1.0f);
  const double a = h.color[3];
  return h.loss + weight * ((1.0 - gate) * a * (1.0 - a) + clear * gate * a);
}

TEST(Render, OpacityPriorGradientMatchesFiniteDifferences) {
  Rays r = random_rays(8, 11);
  for (auto& s : r.sigma) s *= 0.2f;  // partly transparent rays: the prior's gradient is largest there
  const float step = 0.02f, weight = 0.5f, clear = 2.0f;
  int checked = 0;
  for (float gate : {0.0f, 0.4f, 1.0f}) {
    for (uint32_t ray = 1; ray < 8; ++ray) {
      uint32_t first = r.offsets[ray], count = r.counts[ray];
      std::vector<float> dsigma(r.stride), drgb(3 * r.stride);
      const HostRay h = host_ray(r, ray, step, LOSS_L2_SRGB, 1.0f, &dsigma, &drgb);
      float prior =
          render_ray_opacity_prior(first, h.used, step, h.color, weight, clear, gate, 1.0f, dsigma.data());
      const float a = h.color[3];
      EXPECT_NEAR(prior, weight * ((1.0f - gate) * a * (1.0f - a) + clear * gate * a), 1e-6);
      for (uint32_t k = 0; k < count; ++k) {
        uint32_t i = first + k;
        // Same step sizes and tolerance as GradientsMatchFiniteDifferences.
        float save = r.sigma[i];
        r.sigma[i] = save + 1e-2f;
        double lp = host_loss_with_prior(r, ray, step, weight, clear, gate);
        r.sigma[i] = save - 1e-2f;
        double lm = host_loss_with_prior(r, ray, step, weight, clear, gate);
        r.sigma[i] = save;
        double g = (lp - lm) / 2e-2;
        EXPECT_NEAR(dsigma[i], g, 1e-4 + 0.01 * std::fabs(g))
            << "gate " << gate << " ray " << ray << " sample " << k;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 150);
}

TEST(Render, RoomGateFollowsTheSrgbDifference) {
  // Colours chosen in sRGB and decoded to linear, so the RMS sRGB difference is exact: a uniform
  // difference d on every channel gives e = d.
  auto linear = [](float s) { return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f); };
  const float target[3] = {linear(0.50f), linear(0.30f), linear(0.70f)};
  const float same[3] = {target[0], target[1], target[2]};
  const float near[3] = {linear(0.52f), linear(0.32f), linear(0.72f)};  // e = 0.02
  const float far[3] = {linear(0.60f), linear(0.40f), linear(0.80f)};   // e = 0.10
  EXPECT_NEAR(render_ray_room_gate(target, same, 0.05f), 1.0f, 1e-6);
  // float32 sRGB round trip: ~1e-6 in e, / tolerance 0.05 -> 2e-5 in the gate.
  EXPECT_NEAR(render_ray_room_gate(target, near, 0.05f), 1.0f - 0.02f / 0.05f, 1e-4);
  EXPECT_EQ(render_ray_room_gate(target, far, 0.05f), 0.0f);
  EXPECT_EQ(render_ray_room_gate(target, same, 0.0f), 0.0f);  // tolerance 0: no gate
  // One channel off by 0.06: e = 0.06 / sqrt(3).
  const float one[3] = {linear(0.56f), target[1], target[2]};
  EXPECT_NEAR(render_ray_room_gate(target, one, 0.05f), 1.0f - 0.06f / std::sqrt(3.0f) / 0.05f, 1e-4);
}

TEST(Render, KernelWithOpacityPriorMatchesHostReference) {
  Runtime rt({"", "", false});
  Rays r = random_rays(200, 5);
  const float step = 0.015f, weight = 0.25f, clear = 3.0f, tolerance = 0.4f;
  Out plain = run_kernel(rt, r, step, LOSS_L2_SRGB, 0, 0.0f);
  for (float c : {0.0f, clear}) {
    Out o = run_kernel(rt, r, step, LOSS_L2_SRGB, 0, weight, c, tolerance);
    std::vector<float> dsigma(r.stride, 0.0f), drgb(3 * r.stride, 0.0f);
    double changed = 0.0;
    int gated = 0;
    for (uint32_t ray = 0; ray < 200; ++ray) {
      const float* info = &r.info[RAY_INFO_FLOATS * ray];
      const HostRay h = host_ray(r, ray, step, LOSS_L2_SRGB, 1.0f / 600.0f, &dsigma, &drgb);
      const float gate = c > 0.0f ? render_ray_room_gate(info, info + 3, tolerance) : 0.0f;
      gated += gate > 0.0f && r.counts[ray] > 0;
      render_ray_opacity_prior(r.offsets[ray], h.used, step, h.color, weight, c, gate, 1.0f / 200.0f,
                               dsigma.data());
      EXPECT_NEAR(o.loss[ray], h.loss, 1e-5 * std::fabs(h.loss) + 1e-7) << ray;  // the colour loss only
    }
    for (uint32_t i = 0; i < r.stride - 5; ++i) {
      EXPECT_NEAR(o.dsigma[i], dsigma[i], 1e-4 * std::fabs(dsigma[i]) + 1e-8)
          << "clear " << c << " sample " << i;
      changed += std::fabs(o.dsigma[i] - plain.dsigma[i]);
    }
    EXPECT_GT(changed, 1e-3);  // the prior reached the kernel's gradient
    if (c > 0.0f) {
      EXPECT_GT(gated, 20) << "the random rays should open the gate on some rays";
    }
  }
}

// The prior's zones: samples in keep cells get the binary prior's gradient, samples in lean cells
// (and not keep) the gradient with the gate raised to lean_gate, the rest the ray's gate. The kernel
// sample by sample against host builds of the three ray-level priors (render_ray_opacity_prior).
TEST(Render, PriorZonesPickTheGatePerSample) {
  Runtime rt({"", "", false});
  Rays r = random_rays(200, 9);
  for (uint32_t ray = 0; ray < 200; ++ray)
    r.info[RAY_INFO_FLOATS * ray + RAY_INFO_FAR] = 0.0f;  // no far share
  const float step = 0.015f, weight = 0.25f, clear = 3.0f, tolerance = 0.4f, lean_gate = 0.6f;
  const uint32_t res = 4, words = occ_word_count(res);
  std::vector<uint32_t> zones(4 * words, 0u);  // keep, lean; no solid or reach cells (solid_prior_test.cpp)
  std::mt19937 gen(3);
  for (uint32_t c = 0; c < res * res * res; ++c)
    for (uint32_t z = 0; z < 2; ++z)
      if (gen() % 2) zones[z * words + (c >> 5)] |= 1u << (c & 31u);
  Out masked = run_kernel(rt, r, step, LOSS_L2_SRGB, 0, weight, clear, tolerance, zones, res, lean_gate);
  // The colour loss's gradient, then each ray-level prior added to its own copy.
  std::vector<float> base(r.stride, 0.0f), drgb(3 * r.stride, 0.0f);
  for (uint32_t ray = 0; ray < 200; ++ray) host_ray(r, ray, step, LOSS_L2_SRGB, 1.0f / 600.0f, &base, &drgb);
  std::vector<float> binary = base, gated = base, lean = base;
  int gate_open = 0;
  for (uint32_t ray = 0; ray < 200; ++ray) {
    const float* info = &r.info[RAY_INFO_FLOATS * ray];
    const HostRay h = host_ray(r, ray, step, LOSS_L2_SRGB, 1.0f / 600.0f);
    const float gate = render_ray_room_gate(info, info + 3, tolerance);
    gate_open += gate > 0.0f && h.used > 0;
    const uint32_t first = r.offsets[ray];
    render_ray_opacity_prior(first, h.used, step, h.color, weight, clear, 0.0f, 1.0f / 200.0f, binary.data());
    render_ray_opacity_prior(first, h.used, step, h.color, weight, clear, gate, 1.0f / 200.0f, gated.data());
    render_ray_opacity_prior(first, h.used, step, h.color, weight, clear, std::max(gate, lean_gate),
                             1.0f / 200.0f, lean.data());
  }
  int count[3] = {0, 0, 0};
  for (uint32_t i = 0; i < r.stride - 5; ++i) {
    const float x = r.pos[i], y = r.pos[r.stride + i], z = r.pos[2 * r.stride + i];
    const int zone = occ_test(zones.data(), res, x, y, z)           ? 0
                     : occ_test(zones.data() + words, res, x, y, z) ? 1
                                                                    : 2;
    const float want = (zone == 0 ? binary : zone == 1 ? lean : gated)[i];
    // Same tolerance as the other kernel-against-host comparisons.
    EXPECT_NEAR(masked.dsigma[i], want, 1e-4 * std::fabs(want) + 1e-8) << "sample " << i << " zone " << zone;
    count[zone] += masked.dsigma[i] != base[i];
  }
  EXPECT_GT(gate_open, 20) << "the random rays should open the gate on some rays";
  for (int zone = 0; zone < 3; ++zone) EXPECT_GT(count[zone], 50) << "zone " << zone;
  // The zones changed the gradient: lean differs from the ray's gate where that gate is below 0.6.
  double lean_vs_gated = 0.0;
  for (uint32_t i = 0; i < r.stride - 5; ++i) lean_vs_gated += std::fabs(lean[i] - gated[i]);
  EXPECT_GT(lean_vs_gated, 1e-3);
}

// The neck's keep cells with the skin's colours (loss.cl, render_ray_keep_gate): a keep sample gets
// the ray's gate where the ray's pixel is no skin colour and, where it may be skin, the gate times the
// ray's far share (random in [0, 1): the binary prior at 0). The kernel sample by sample against the
// host builds; the skin colours are two of the rays' own pixels, so both cases occur.
TEST(Render, KeepCellsClearRaysOfNoSkinColour) {
  Runtime rt({"", "", false});
  Rays r = random_rays(200, 11);
  const float step = 0.015f, weight = 0.25f, clear = 3.0f, tolerance = 0.4f, skin_tolerance = 0.08f;
  const uint32_t res = 4, words = occ_word_count(res);
  std::vector<uint32_t> zones(4 * words, 0u);
  for (uint32_t w = 0; w < words; ++w) zones[w] = ~0u;  // every cell keeps
  std::vector<float> skin;
  for (uint32_t ray : {3u, 5u}) {
    const float* px = &r.info[RAY_INFO_FLOATS * ray];
    const float sum = px[0] + px[1] + px[2];
    skin.insert(skin.end(), {px[0] / sum, px[1] / sum});
  }
  Out out = run_kernel(rt, r, step, LOSS_L2_SRGB, 0, weight, clear, tolerance, zones, res, 0.0f, skin,
                       skin_tolerance);
  std::vector<float> want(r.stride, 0.0f), drgb(3 * r.stride, 0.0f);
  int skin_like = 0, cleared = 0;
  for (uint32_t ray = 0; ray < 200; ++ray) {
    const float* info = &r.info[RAY_INFO_FLOATS * ray];
    const HostRay h = host_ray(r, ray, step, LOSS_L2_SRGB, 1.0f / 600.0f, &want, &drgb);
    const float gate = render_ray_room_gate(info, info + 3, tolerance);
    const float keep =
        render_ray_keep_gate(info, gate, skin.data(), 2, skin_tolerance, 0.0f, info[RAY_INFO_FAR]);
    if (h.used == 0) continue;
    skin_like += render_ray_skin_like(info, skin.data(), 2, skin_tolerance, 0.0f);
    cleared += keep > 0.0f;
    render_ray_opacity_prior(r.offsets[ray], h.used, step, h.color, weight, clear, keep, 1.0f / 200.0f,
                             want.data());
  }
  for (uint32_t i = 0; i < r.stride - 5; ++i)
    EXPECT_NEAR(out.dsigma[i], want[i], 1e-4 * std::fabs(want[i]) + 1e-8) << "sample " << i;
  EXPECT_GT(skin_like, 5) << "some rays' pixels should be skin";
  EXPECT_GT(cleared, 5) << "some rays of no skin colour should have the gate open";
}

// far_share (loss.cl) against its host build, render_ray_share_beyond, on random rays and a random
// box, with and without a column below a base plane; and on single rays against closed forms: a slab
// of opacity a inside the box, then one beyond it; the same slab below the base plane, near within the
// column and far beside it.
TEST(Render, FarShareMatchesHostReference) {
  Runtime rt({"", "", false});
  Rays r = random_rays(200, 13);
  const float step = 0.015f;
  const uint32_t n = 200;
  Buffer<uint32_t> off(rt, r.offsets), cnt(rt, r.counts);
  Buffer<float> sigma(rt, r.sigma), pos(rt, r.pos), share(rt, n);
  Kernel k(rt.program("train/loss.cl"), "far_share");
  LossParams p{};
  p.n_rays = n, p.stride = r.stride, p.step = step, p.min_transmittance = 1e-4f;
  const float lo[3] = {0.2f, 0.1f, 0.3f}, hi[3] = {0.7f, 0.9f, 0.6f};
  for (int a = 0; a < 3; ++a) p.near.lo[a] = lo[a], p.near.hi[a] = hi[a];
  std::vector<float> plain;
  for (const float radius : {0.0f, 0.12f}) {
    // A base plane across the box's middle, its up axis tilted as a head's may be.
    const float up[3] = {0.2f, 0.96f, 0.1f}, len = std::sqrt(0.04f + 0.9216f + 0.01f);
    for (int a = 0; a < 3; ++a) p.near.base[a] = 0.45f, p.near.up[a] = up[a] / len;
    p.near.base_radius = radius;
    k.args(p, off, cnt, sigma, pos, share).launch(rt, n, 64);
    const std::vector<float> got = share.read(rt);
    int partial = 0;
    for (uint32_t ray = 0; ray < n; ++ray) {
      const float want = render_ray_share_beyond(r.sigma.data(), r.pos.data(), r.stride, r.offsets[ray],
                                                 r.counts[ray], step, 1e-4f, &p.near);
      EXPECT_NEAR(got[ray], want, 1e-5) << ray;
      partial += want > 0.05f && want < 0.95f;
    }
    EXPECT_GT(partial, 20) << "the random rays should split between the box and beyond";
    if (radius == 0.0f)
      plain = got;
    else
      EXPECT_GT(std::inner_product(got.begin(), got.end(), plain.begin(), 0.0f, std::plus<>(),
                                   [](float c, float b) { return float(c > b + 1e-4f); }),
                20.0f)
          << "the column should make some rays' samples below the plane far";
  }
  // Ten samples inside the box (opacity a = 1 - exp(-10 sigma step)), then ten beyond: 1 - a.
  const uint32_t N = 20;
  std::vector<float> s(N, 20.0f), q(3 * N, 0.5f);
  for (uint32_t i = 10; i < N; ++i) q[2 * N + i] = 0.95f;  // z beyond hi[2]
  const float a = 1.0f - std::exp(-10.0f * 20.0f * step);
  NearRegion box{};
  for (int k3 = 0; k3 < 3; ++k3) box.lo[k3] = lo[k3], box.hi[k3] = hi[k3];
  EXPECT_NEAR(render_ray_share_beyond(s.data(), q.data(), N, 0, N, step, 1e-4f, &box), 1.0f - a, 1e-5);
  // The first ten below a level base plane at y = 0.5 (up +y), 0.05 off its axis, then ten beyond
  // the box: near (1 - a) within a column of 0.06, far (1) within one of 0.04.
  for (uint32_t i = 0; i < 10; ++i) q[N + i] = 0.3f, q[i] = 0.5f + 0.05f;
  NearRegion column = box;
  column.base[0] = column.base[1] = column.base[2] = 0.5f, column.up[1] = 1.0f;
  column.base_radius = 0.06f;
  EXPECT_NEAR(render_ray_share_beyond(s.data(), q.data(), N, 0, N, step, 1e-4f, &column), 1.0f - a, 1e-5);
  column.base_radius = 0.04f;
  EXPECT_NEAR(render_ray_share_beyond(s.data(), q.data(), N, 0, N, step, 1e-4f, &column), 1.0f, 1e-5);
}

TEST(Render, KernelMatchesHostReference) {
  Runtime rt({"", "", false});
  Rays r = random_rays(200, 3);
  const float step = 0.015f;
  Out o = run_kernel(rt, r, step, LOSS_L2_SRGB, 0);
  std::vector<float> dsigma(r.stride, 0.0f), drgb(3 * r.stride, 0.0f);
  for (uint32_t ray = 0; ray < 200; ++ray) {
    const HostRay h = host_ray(r, ray, step, LOSS_L2_SRGB, 1.0f / 600.0f, &dsigma, &drgb);
    const float* color = h.color;
    const float loss = h.loss;
    // Same float32 formulas on both sides; the device may contract to FMA or use a different exp/pow
    // (OpenCL allows a few ulp): 1e-5 relative + 1e-7 absolute.
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(o.color[4 * ray + c], color[c], 1e-5) << ray;
    EXPECT_NEAR(o.loss[ray], loss, 1e-5 * std::fabs(loss) + 1e-7) << ray;
  }
  for (uint32_t i = 0; i < r.stride - 5; ++i) {
    EXPECT_NEAR(o.dsigma[i], dsigma[i], 1e-4 * std::fabs(dsigma[i]) + 1e-8) << i;
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(o.drgb[c * r.stride + i], drgb[c * r.stride + i],
                  1e-4 * std::fabs(drgb[c * r.stride + i]) + 1e-8);
  }
}

}  // namespace
