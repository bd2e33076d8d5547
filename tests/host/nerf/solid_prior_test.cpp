// The opacity prior's zones (kernels/train/render.h render_ray_opacity_prior_zones) on the host, the
// kernels' own code: a ray's samples in the solid zone get the pull towards an opaque ray (-pull x
// weight x ray scale, times step x T), whatever the room gate says; a sample in the keep zone gets the
// binary prior; one in no zone the gated prior; a sample in both solid and keep cells is solid.
#include <gtest/gtest.h>

#include <vector>

#include "kernels/train/occupancy.h"
#include "kernels/train/render.h"

namespace {

constexpr uint32_t kRes = 4;

void set_cell(std::vector<uint32_t>& bits, size_t field, float x, float y, float z) {
  const int c = occ_cell_index(kRes, x, y, z);
  bits[field * occ_word_count(kRes) + (uint32_t(c) >> 5)] |= 1u << (uint32_t(c) & 31u);
}

TEST(SolidPrior, SolidCellsPullTowardsOpaqueWhateverTheGate) {
  // Four samples (SoA positions): solid, keep, none, solid and keep.
  const float xs[4] = {0.1f, 0.6f, 0.9f, 0.35f}, ys[4] = {0.1f, 0.6f, 0.9f, 0.35f},
              zs[4] = {0.1f, 0.6f, 0.9f, 0.35f};
  std::vector<float> pos;
  for (const float* c : {xs, ys, zs}) pos.insert(pos.end(), c, c + 4);
  std::vector<uint32_t> zones(3 * occ_word_count(kRes), 0u);
  set_cell(zones, 2, xs[0], ys[0], zs[0]);
  set_cell(zones, 0, xs[1], ys[1], zs[1]);
  set_cell(zones, 0, xs[3], ys[3], zs[3]);
  set_cell(zones, 2, xs[3], ys[3], zs[3]);
  const float color[4] = {0.5f, 0.5f, 0.5f, 0.3f};  // a ray 30 % opaque: a hole
  const float step = 0.01f, weight = 0.03f, clear = 1.0f, gate = 1.0f, pull = 2.0f, scale = 0.25f;
  std::vector<float> dsigma(4, 0.0f);
  render_ray_opacity_prior_zones(0, 4, step, color, weight, clear, gate, 0.0f, pull, scale, pos.data(), 4,
                                 zones.data(), kRes, dsigma.data());
  const float T = 1.0f - color[3];
  const float solid = -pull * weight * scale;
  const float binary = weight * scale * (1.0f - 2.0f * color[3]);  // gate 0
  const float gated = weight * scale * clear;                      // gate 1: the clearing
  EXPECT_FLOAT_EQ(dsigma[0], step * T * solid);
  EXPECT_FLOAT_EQ(dsigma[1], step * T * binary);
  EXPECT_FLOAT_EQ(dsigma[2], step * T * gated);
  EXPECT_FLOAT_EQ(dsigma[3], step * T * solid);
  EXPECT_LT(dsigma[0], 0.0f);  // descent raises the density: the ray becomes opaque
  EXPECT_GT(dsigma[2], 0.0f);  // the clearing would lower it
}

}  // namespace
