// The room-explained clearing's gate with the subject's own evidence (kernels/train/render.h
// render_ray_clear_gate) on the host, the kernels' own code, against an analytic scene: a ray through
// a shell of hair above a head, missing the head's certain interior, before a plain wall. The hair's
// strands are shaded about the wall's colour, so the room's colour lies within the gate's tolerance of
// the pixel (the room "explains" it in part) while the hair explains it exactly; a haze of the
// wall's own colour explains nothing the room does not. Training is plain gradient descent on the
// samples' densities with the colour loss and the prior together, as the loss kernel computes them.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "kernels/train/occupancy.h"
#include "kernels/train/render.h"

namespace {

constexpr uint32_t kRes = 32, kSamples = 64;
constexpr float kStep = 1.0f / kSamples;
constexpr float kWeight = 0.03f, kClear = 1.0f, kTolerance = 0.05f, kLeanGate = 1.0f, kSolidPull = 1.0f;
constexpr float kInterior = 0.2f;  // the certain interior: a sphere about the box's centre

float linear(float s) { return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f); }

// Zone bitfields (keep, lean, solid, reach): the interior, and where a ray counts as crossing it (the
// interior grown to radius `reach`); the hair lies in the core (the ray's gate).
std::vector<uint32_t> interior_zones(float reach = kInterior) {
  std::vector<uint32_t> bits(4 * occ_word_count(kRes), 0u);
  for (uint32_t c = 0; c < kRes * kRes * kRes; ++c) {
    const float x = (float(c % kRes) + 0.5f) / kRes - 0.5f, y = (float(c / kRes % kRes) + 0.5f) / kRes - 0.5f,
                z = (float(c / (kRes * kRes)) + 0.5f) / kRes - 0.5f;
    const float r2 = x * x + y * y + z * z;
    for (uint32_t field : {2u, 3u})
      if (r2 < (field == 2u ? kInterior * kInterior : reach * reach))
        bits[field * occ_word_count(kRes) + (c >> 5)] |= 1u << (c & 31u);
  }
  return bits;
}

// A ray along z at height `y` (0.8: 0.3 above the interior's centre, 0.1 above the interior) with a slab z in
// [0.3, 0.4) of optical depth `tau` and colour `rgb` (linear) at every sample.
struct Ray {
  std::vector<float> pos, sigma, rgb;
};
Ray slab(float tau, const float* rgb, float y = 0.8f) {
  Ray r;
  r.pos.resize(3 * kSamples);
  r.sigma.assign(kSamples, 0.0f);
  r.rgb.resize(3 * kSamples);
  auto in_slab = [](uint32_t k) {
    return (float(k) + 0.5f) * kStep > 0.3f && (float(k) + 0.5f) * kStep < 0.4f;
  };
  uint32_t n = 0;
  for (uint32_t k = 0; k < kSamples; ++k) n += in_slab(k);
  for (uint32_t k = 0; k < kSamples; ++k) {
    r.pos[k] = 0.5f, r.pos[kSamples + k] = y, r.pos[2 * kSamples + k] = (float(k) + 0.5f) * kStep;
    for (int c = 0; c < 3; ++c) r.rgb[c * kSamples + k] = rgb[c];
    if (in_slab(k)) r.sigma[k] = tau / (float(n) * kStep);
  }
  return r;
}

float opacity(const Ray& r) {
  float T = 1.0f;
  for (float s : r.sigma) T *= std::exp(-s * kStep);
  return 1.0f - T;
}

// `steps` of descent on the densities with the loss kernel's gradient: the colour loss (the pixel
// `pixel` over the room's colour `wall`) and the zones' prior with the gate of render_ray_clear_gate
// at `margin` (0: the room gate alone), with `zones`. Returns the ray's final opacity.
float train(Ray r, const float* pixel, const float* wall, float margin, int steps,
            const std::vector<uint32_t>& zones = interior_zones()) {
  for (int it = 0; it < steps; ++it) {
    float color[4], dC[3];
    std::vector<float> dsigma(kSamples, 0.0f), drgb(3 * kSamples, 0.0f);
    const uint32_t used =
        render_ray_forward(r.sigma.data(), r.rgb.data(), kSamples, 0, kSamples, kStep, 1e-4f, wall, color);
    render_ray_loss(color, pixel, LOSS_L2_SRGB, 1.0f / 3.0f, dC);
    render_ray_backward(r.sigma.data(), r.rgb.data(), kSamples, 0, kSamples, used, kStep, color, dC,
                        dsigma.data(), drgb.data());
    const float gate = render_ray_clear_gate(pixel, wall, color, kTolerance, margin);
    render_ray_opacity_prior_zones(0, kSamples, used, kStep, color, kWeight, kClear, gate, 0.0f, 0.0f,
                                   kLeanGate, kSolidPull, 1.0f, r.pos.data(), kSamples, zones.data(), kRes,
                                   dsigma.data());
    for (uint32_t k = 0; k < kSamples; ++k) r.sigma[k] = std::fmax(0.0f, r.sigma[k] - 2e4f * dsigma[k]);
  }
  return opacity(r);
}

// The wall (sRGB 244, 242, 238) and a strand 0.015 darker on every channel (RMS sRGB 0.015: the room
// gate reads 0.7), as the hair of the wall's colour, shaded strand by strand, is in hair_wall.
const float kWall[3] = {linear(244 / 255.f), linear(242 / 255.f), linear(238 / 255.f)};
const float kStrand[3] = {linear(244 / 255.f - 0.015f), linear(242 / 255.f - 0.015f),
                          linear(238 / 255.f - 0.015f)};

TEST(ClearGate, TheSubjectsOwnEvidenceClosesTheGate) {
  const float composite_exact[3] = {kStrand[0], kStrand[1], kStrand[2]};
  const float room_only[3] = {kWall[0], kWall[1], kWall[2]};
  // float32 sRGB round trips: ~1e-6 in the RMS, / 0.05 -> 2e-5 in a gate.
  const float room = render_ray_room_gate(kStrand, kWall, kTolerance);
  ASSERT_NEAR(room, 1.0f - 0.015f / 0.05f, 1e-4);
  EXPECT_FLOAT_EQ(render_ray_clear_gate(kStrand, kWall, composite_exact, kTolerance, 0.0f), room) << "off";
  // The render explains the pixel exactly: d = 0.015; margin 0.03 halves the gate, 0.01 closes it.
  EXPECT_NEAR(render_ray_clear_gate(kStrand, kWall, composite_exact, kTolerance, 0.03f), 0.5f * room, 1e-4);
  EXPECT_EQ(render_ray_clear_gate(kStrand, kWall, composite_exact, kTolerance, 0.01f), 0.0f);
  // A transparent ray renders the room's colour (d = 0): the room gate as it is.
  EXPECT_NEAR(render_ray_clear_gate(kStrand, kWall, room_only, kTolerance, 0.02f), room, 1e-6);
  // A render further from the pixel than the room (d < 0) does not open the gate past the room's.
  const float worse[3] = {linear(0.5f), linear(0.5f), linear(0.5f)};
  EXPECT_NEAR(render_ray_clear_gate(kStrand, kWall, worse, kTolerance, 0.02f), room, 1e-6);
  // A pixel the room does not explain stays closed.
  EXPECT_EQ(render_ray_clear_gate(worse, kWall, composite_exact, kTolerance, 0.02f), 0.0f);
}

// The hair of hair_wall (#41): opaque strands (opacity 0.9 when the prior ramps in) that the room's
// colour explains in part are cleared by the room gate alone, the colour loss's gradient being far
// weaker than the clearing's near the wall's colour; with the subject's evidence (margin 0.02) they
// stay. A haze of the wall's colour, partly transparent, is cleared either way: the rule spares only
// what the subject explains better than the room.
TEST(ClearGate, HairShadedAboutTheWallsColourStaysAndTheWallsHazeClears) {
  const float tau_hair = -std::log(0.1f), tau_haze = -std::log(0.6f);
  const Ray hair = slab(tau_hair, kStrand), haze = slab(tau_haze, kWall);
  ASSERT_NEAR(opacity(hair), 0.9f, 1e-4);
  ASSERT_NEAR(opacity(haze), 0.4f, 1e-4);
  EXPECT_LT(train(hair, kStrand, kWall, 0.0f, 2000), 0.5f) << "the room gate alone clears the hair";
  EXPECT_GT(train(hair, kStrand, kWall, 0.02f, 2000), 0.9f) << "the hair the subject explains stays";
  EXPECT_LT(train(haze, kWall, kWall, 0.02f, 2000), 0.05f) << "the wall's haze clears";
  EXPECT_LT(train(haze, kWall, kWall, 0.0f, 2000), 0.05f);
}

// The crossing judged within a reach of the interior (render.h's "reach" field,
// BackgroundOptions::solid_reach_mm): the hair's ray passes 0.1 above the interior, so the clearing
// takes it with the interior alone and leaves it to the binary prior within a reach of 0.12; a haze
// 0.22 above the interior, beyond that reach, still clears. The pull stays in the interior itself,
// so the reach adds no density where the ray does not already hold some.
TEST(ClearGate, ARayWithinTheReachOfTheInteriorIsTheSubjects) {
  const std::vector<uint32_t> reach = interior_zones(kInterior + 0.12f);
  const Ray hair = slab(-std::log(0.1f), kStrand), haze = slab(-std::log(0.6f), kWall, 0.92f);
  const Ray empty = slab(0.0f, kStrand);
  EXPECT_LT(train(hair, kStrand, kWall, 0.0f, 2000), 0.5f) << "the interior alone: cleared";
  EXPECT_GT(train(hair, kStrand, kWall, 0.0f, 2000, reach), 0.9f) << "within the reach: the subject's";
  EXPECT_LT(train(haze, kWall, kWall, 0.0f, 2000, reach), 0.05f) << "beyond the reach: cleared";
  EXPECT_EQ(train(empty, kWall, kWall, 0.0f, 2000, reach), 0.0f) << "no density added outside the interior";
}

}  // namespace
