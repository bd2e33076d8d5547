// The clearing in the neck's keep zone (kernels/train/render.h render_ray_skin_like,
// render_ray_keep_gate, render_ray_opacity_prior_zones) on the host, the kernels' own code, against
// an analytic scene: a neck (a vertical cylinder of pale skin) in the keep zone, the room model's
// body of the skin's colour right behind it, and beside it a slab of haze of the wall's colour, the
// room model explaining the wall behind it (the room's gate fully open on both rays). The colour loss
// gives no gradient on either ray (each renders its pixel's colour whatever its opacity), so the
// prior alone decides.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "kernels/train/occupancy.h"
#include "kernels/train/render.h"

namespace {

constexpr uint32_t kRes = 32, kSamples = 64;
constexpr float kStep = 1.0f / kSamples;
constexpr float kWeight = 0.03f, kClear = 1.0f, kGate = 1.0f, kLeanGate = 1.0f, kScale = 1.0f;
constexpr float kNeck = 0.15f;  // the neck's radius about the box's vertical axis
// Linear colours: pale skin (sRGB 250,228,215) and an off-white wall (244,242,238): chromaticities
// 0.397,0.320 and 0.343,0.337, 0.057 apart.
constexpr std::array<float, 3> kSkin{0.956f, 0.776f, 0.680f}, kOffWhite{0.905f, 0.888f, 0.855f};
constexpr float kTolerance = 0.02f;

std::array<float, 2> chroma(const std::array<float, 3>& c) {
  const float s = c[0] + c[1] + c[2];
  return {c[0] / s, c[1] / s};
}

// The keep zone: the cells within 0.35 of the vertical axis (the neck and the space beside it, as
// wide as a head); no lean or solid cells; with `reach`, the reach cells within the neck's radius of
// the axis (a neck's core grown towards its skin).
std::vector<uint32_t> keep_zone(bool reach = false) {
  std::vector<uint32_t> bits(4 * occ_word_count(kRes), 0u);
  for (uint32_t c = 0; c < kRes * kRes * kRes; ++c) {
    const float x = (float(c % kRes) + 0.5f) / kRes - 0.5f,
                z = (float(c / (kRes * kRes)) + 0.5f) / kRes - 0.5f;
    if (x * x + z * z < 0.35f * 0.35f) bits[c >> 5] |= 1u << (c & 31u);
    if (reach && x * x + z * z < kNeck * kNeck) bits[3 * occ_word_count(kRes) + (c >> 5)] |= 1u << (c & 31u);
  }
  return bits;
}

// One ray along z at x (y = 0.5) with density `sigma` where it crosses the neck (its outer 0.05) or,
// beside the neck, the haze slab 0.1 deep in front of the axis' depth.
struct Ray {
  std::vector<float> pos, sigma;
};
Ray ray_at(float x, float sigma) {
  Ray r;
  r.pos.resize(3 * kSamples);
  r.sigma.assign(kSamples, 0.0f);
  for (uint32_t k = 0; k < kSamples; ++k) {
    const float z = (float(k) + 0.5f) * kStep, d = std::hypot(x - 0.5f, z - 0.5f);
    r.pos[k] = x, r.pos[kSamples + k] = 0.5f, r.pos[2 * kSamples + k] = z;
    const bool neck = d < kNeck && d > kNeck - 0.05f,
               slab = std::fabs(x - 0.5f) > kNeck && z > 0.3f && z < 0.4f;
    if (neck || slab) r.sigma[k] = sigma;
  }
  return r;
}

float opacity(const Ray& r) {
  float T = 1.0f;
  for (float s : r.sigma) T *= std::exp(-s * kStep);
  return 1.0f - T;
}

// Plain gradient descent on the samples' densities with the prior alone, the keep cells' gate from
// the pixel `pixel` against the skin's chromaticities (none: the rule off); the final opacity.
// `far`: the share of the room's colour from beyond the body (render_ray_keep_gate; 0: the room's body
// right behind, as the neck's rays see it).
float descend(Ray r, const std::array<float, 3>& pixel, const std::vector<std::array<float, 2>>& skin,
              float keep_pull = 0.0f, float far = 0.0f, int steps = 400) {
  const std::vector<uint32_t> zones = keep_zone(keep_pull > 0.0f);
  std::vector<float> chroma_pairs;
  for (const auto& c : skin) chroma_pairs.insert(chroma_pairs.end(), {c[0], c[1]});
  const float keep_gate = render_ray_keep_gate(pixel.data(), kGate, chroma_pairs.data(),
                                               uint32_t(skin.size()), kTolerance, 0.01f, far);
  for (int it = 0; it < steps; ++it) {
    const float color[4] = {pixel[0], pixel[1], pixel[2], opacity(r)};
    std::vector<float> dsigma(kSamples, 0.0f);
    render_ray_opacity_prior_zones(0, kSamples, kSamples, kStep, color, kWeight, kClear, kGate, keep_gate,
                                   keep_pull, kLeanGate, 0.0f, kScale, r.pos.data(), kSamples, zones.data(),
                                   kRes, dsigma.data());
    for (uint32_t k = 0; k < kSamples; ++k) r.sigma[k] = std::fmax(0.0f, r.sigma[k] - 2e4f * dsigma[k]);
  }
  return opacity(r);
}

// Haze at 60 % opacity when the prior ramps in: the keep zone's binary prior alone makes it solid
// (#41's slab beside the neck); with the skin's colours known, its off-white pixel matches none of
// them and the slab clears. The neck itself, its pixel the skin's colour and the body behind it too,
// keeps the binary prior and becomes opaque, as without the rule.
TEST(NeckClear, HazeOfTheWallsColourBesideTheNeckClearsAndTheNeckStays) {
  const float sigma = -std::log(0.4f) / 0.1f;  // the slab's 0.1 of depth: opacity 0.6
  const Ray slab = ray_at(0.5f + 0.25f, sigma), neck = ray_at(0.5f, sigma);
  ASSERT_GT(opacity(slab), 0.55f);  // the slab spans 7 samples of 1/64: opacity 0.63
  ASSERT_LT(opacity(slab), 0.7f);
  ASSERT_GT(opacity(neck), 0.55f);
  const std::vector<std::array<float, 2>> skin{chroma(kSkin)}, unknown;
  EXPECT_GT(descend(slab, kOffWhite, unknown), 0.95f) << "without the skin's colours the slab becomes solid";
  EXPECT_LT(descend(slab, kOffWhite, skin), 0.05f) << "a pixel of no skin colour clears the slab";
  EXPECT_GT(descend(neck, kSkin, skin), 0.95f) << "the neck's own pixel keeps the binary prior";
  EXPECT_LT(descend(neck, kSkin, {chroma(kOffWhite)}), 0.05f) << "judged no skin, the neck would be cleared";
}

// Before a wall of the skin's own colour the pixel beside the neck matches the skin: where the room's
// colour behind it is its body's (far share 0), the skin test leaves the binary prior there (the slab
// becomes solid as without the test, no worse).
TEST(NeckClear, AWallOfTheSkinsColourKeepsTheBinaryPrior) {
  const Ray slab = ray_at(0.5f + 0.25f, -std::log(0.4f) / 0.1f);
  EXPECT_GT(descend(slab, kSkin, {chroma(kSkin)}), 0.95f);
}

// Before a wall of the skin's own colour, with the room's colour behind the slab coming from that
// wall (far share 1; no body behind it): the slab clears as haze does in the bare head's zone. The
// neck's rays see the room's body right behind (far share 0) and keep the binary prior; a neck ray
// that the room explained through the wall alone would be cleared, unless it crosses the neck's
// reach, whose rays keep the binary prior and the pull whatever the room's colour.
TEST(NeckClear, AWallOfTheSkinsColourFarBehindClearsTheSlab) {
  const float sigma = -std::log(0.4f) / 0.1f;
  const Ray slab = ray_at(0.5f + 0.25f, sigma), neck = ray_at(0.5f, sigma);
  const std::vector<std::array<float, 2>> skin{chroma(kSkin)};
  EXPECT_LT(descend(slab, kSkin, skin, 0.0f, 1.0f), 0.05f) << "the wall far behind: the slab clears";
  EXPECT_GT(descend(slab, kSkin, skin, 0.0f, 0.0f), 0.95f) << "the body behind: the binary prior";
  EXPECT_LT(descend(slab, kSkin, skin, 0.0f, 0.5f), 0.05f) << "half the room's colour from the wall";
  EXPECT_GT(descend(neck, kSkin, skin, 0.0f, 0.0f), 0.95f) << "the neck before the room's body stays";
  EXPECT_LT(descend(neck, kSkin, skin, 0.0f, 1.0f), 0.05f) << "the neck before the wall alone would go";
  EXPECT_GT(descend(neck, kSkin, skin, 1.0f, 1.0f), 0.95f) << "the neck's reach keeps it";
}

// The neck's lowest band, mostly transparent when the prior ramps in because the room's body below
// the head box explained it first: the binary prior alone clears it; with the keep pull on the
// samples within the reach it becomes opaque, whatever its pixel's colour, while a slab beside the
// neck, outside the reach, keeps the rules it had: one of the off-white wall's colour clears, one of
// the skin's colour (a wall of that colour) is left to the binary prior, as without the pull.
TEST(NeckClear, TheKeepPullFormsTheNecksBandAndLeavesTheSlabBesideIt) {
  const float thin = -std::log(0.7f) / 0.05f;  // the neck's outer 0.05, twice: opacity about 0.5
  const Ray neck = ray_at(0.5f, thin * 0.3f), slab = ray_at(0.5f + 0.25f, -std::log(0.4f) / 0.1f);
  ASSERT_LT(opacity(neck), 0.45f);
  ASSERT_GT(opacity(neck), 0.15f);
  const std::vector<std::array<float, 2>> skin{chroma(kSkin)};
  EXPECT_LT(descend(neck, kSkin, skin), 0.05f) << "the binary prior alone clears the band";
  EXPECT_GT(descend(neck, kSkin, skin, 1.0f), 0.95f) << "the pull keeps it";
  EXPECT_GT(descend(neck, kOffWhite, skin, 1.0f), 0.95f) << "a collar of another colour too";
  EXPECT_LT(descend(slab, kOffWhite, skin, 1.0f), 0.05f) << "beside the reach: cleared as before";
  const Ray faint = ray_at(0.5f + 0.25f, -std::log(0.7f) / 0.1f);  // opacity 0.3 beside the neck
  EXPECT_LT(descend(faint, kSkin, skin, 1.0f), 0.05f) << "beside the reach: the binary prior alone";
}

// The skin test is on chromaticity and a brightness floor: the skin shaded to a third (the neck in
// the jaw's shadow), the skin 3 % redder and the skin under a sheen of white light still match within
// 0.02; a
// pixel darker than the floor is never judged (its chromaticity is noise), whatever its colour; the
// off-white wall, 0.057 from the skin, does not match, nor does a dark wall of another hue.
TEST(NeckClear, SkinTestIsShadingInvariantAndLeavesDarkPixelsUnjudged) {
  const std::array<float, 2> ref = chroma(kSkin);
  const float c[2] = {ref[0], ref[1]};
  const float floor = 0.03f;
  const auto like = [&](std::array<float, 3> px) {
    return render_ray_skin_like(px.data(), c, 1, kTolerance, floor);
  };
  EXPECT_TRUE(like(kSkin));
  EXPECT_TRUE(like({kSkin[0] / 3, kSkin[1] / 3, kSkin[2] / 3})) << "shade";
  EXPECT_TRUE(like({kSkin[0] * 1.03f, kSkin[1], kSkin[2] * 0.99f})) << "a slightly redder skin";
  // A sheen: white light added to the skin's, a quarter of the pixel's (w = sum / 9), moves the
  // chromaticity a quarter of the way to neutral, 0.017 here, inside SKIN_SHEEN_MAX.
  const float w = (kSkin[0] + kSkin[1] + kSkin[2]) / 9.0f;
  EXPECT_TRUE(like({kSkin[0] + w, kSkin[1] + w, kSkin[2] + w})) << "sheen";
  EXPECT_FALSE(like(kOffWhite));
  EXPECT_FALSE(like({0.061f, 0.045f, 0.038f})) << "a dark wall (sRGB 70,60,55), bright enough to judge";
  EXPECT_TRUE(like({0.02f, 0.03f, 0.04f})) << "under the floor: not judged";
  EXPECT_TRUE(like({0.0f, 0.0f, 0.0f})) << "black";
  // Several skin colours: a pixel matching any of them is skin.
  const float two[4] = {0.5f, 0.3f, ref[0], ref[1]};
  EXPECT_TRUE(render_ray_skin_like(kSkin.data(), two, 2, kTolerance, floor));
  EXPECT_FALSE(render_ray_skin_like(kSkin.data(), two, 1, kTolerance, floor)) << "only the first";
  // The keep cells' gate: the ray's gate where the pixel is no skin, else 0; 0 without skin colours.
  EXPECT_FLOAT_EQ(render_ray_keep_gate(kOffWhite.data(), 0.7f, c, 1, kTolerance, floor, 0.0f), 0.7f);
  EXPECT_FLOAT_EQ(render_ray_keep_gate(kSkin.data(), 0.7f, c, 1, kTolerance, floor, 0.0f), 0.0f);
  EXPECT_FLOAT_EQ(render_ray_keep_gate(kOffWhite.data(), 0.7f, c, 0, kTolerance, floor, 0.0f), 0.0f);
  // A pixel that may be skin: the gate times the room's far share; no skin colours known: the same.
  EXPECT_FLOAT_EQ(render_ray_keep_gate(kSkin.data(), 0.7f, c, 1, kTolerance, floor, 0.5f), 0.35f);
  EXPECT_FLOAT_EQ(render_ray_keep_gate(kOffWhite.data(), 0.7f, c, 0, kTolerance, floor, 1.0f), 0.7f);
  EXPECT_FLOAT_EQ(render_ray_keep_gate(kSkin.data(), 0.0f, c, 1, kTolerance, floor, 1.0f), 0.0f);
}

}  // namespace
