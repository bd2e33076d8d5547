// The occupancy update's kept cells (host/nerf/occupancy_update.h set_interior) on PoCL, against the
// same update without them: a subject's interior reach stays occupied whatever the density says
// (render.h judges a ray's crossing of the reach by its samples there), every other cell's bit and the
// interior's count of cells the density left are what the update alone gives, the permanent mask
// still rules a kept cell out, and the grid a snapshot holds is the update's without the kept cells.
#include <gtest/gtest.h>

#include <vector>

#include "host/nerf/occupancy_update.h"
#include "kernels/train/occupancy.h"
#include "sphere_model.h"

namespace {

using namespace lorgnette;
using namespace lorgnette::nerf;

// 8 views of 32 px, models of 2^12 samples per batch, seed 7.
struct Scene : nerftest::SphereModelScene {
  Scene() : SphereModelScene(8, 32) {}
};

bool bit(const std::vector<uint32_t>& bits, uint32_t c) { return (bits[c >> 5] >> (c & 31u)) & 1u; }

// Every `every`-th cell from `first`.
std::vector<uint32_t> cells_every(uint32_t res, uint32_t first, uint32_t every) {
  std::vector<uint32_t> bits(occ_word_count(res), 0u);
  for (uint32_t c = first; c < res * res * res; c += every) bits[c >> 5] |= 1u << (c & 31u);
  return bits;
}

struct Updated {
  OccupancyGrid grid, saved;  // the training's grid and the one a snapshot holds (without_kept)
  uint64_t interior_empty;
};

Updated update_once(Scene& s, const std::vector<uint32_t>& mask, const std::vector<uint32_t>& interior,
                    const std::vector<uint32_t>& kept) {
  NerfModel model = s.make_model();
  OccupancyUpdater u(model, OccupancyOptions{}, 7u, mask);
  u.set_interior(interior, kept);
  u.update(0);
  return {model.occupancy(), u.without_kept(model.occupancy()), u.interior_empty()};
}

// with.grid == plain.grid's bits OR the kept cells the mask allows (an empty mask allows all); counts
// the kept cells that were forced and those the mask kept out.
void expect_plain_or_kept(const Updated& plain, const Updated& with, const std::vector<uint32_t>& mask,
                          const std::vector<uint32_t>& kept, uint32_t& forced, uint32_t& masked_out) {
  forced = masked_out = 0;
  for (uint32_t c = 0; c < uint32_t(plain.grid.density.size()); ++c) {
    const bool allowed = mask.empty() || bit(mask, c), keep = bit(kept, c) && allowed;
    ASSERT_EQ(bit(with.grid.bits, c), bit(plain.grid.bits, c) || keep) << "cell " << c;
    forced += keep && !bit(plain.grid.bits, c);
    masked_out += bit(kept, c) && !allowed && !bit(with.grid.bits, c);
  }
  EXPECT_EQ(with.interior_empty, plain.interior_empty);
  EXPECT_EQ(with.grid.density, plain.grid.density);
  // A snapshot holds the density's own bits: the update's without the kept cells.
  EXPECT_EQ(with.saved.bits, plain.grid.bits);
  EXPECT_EQ(plain.saved.bits, plain.grid.bits);
}

TEST(OccupancyKept, KeptCellsStayOccupiedAndTheRestIsTheUpdatesOwn) {
  Scene s;
  const uint32_t res = s.sizing.occupancy_resolution;
  const std::vector<uint32_t> interior = cells_every(res, 0, 5), kept = cells_every(res, 0, 3);
  // A fresh field's density is about 1 everywhere, so the threshold (capped at the mean density) leaves
  // part of the grid empty, and the kept cells force some of it.
  const Updated plain = update_once(s, {}, interior, {}), with = update_once(s, {}, interior, kept);
  EXPECT_GT(plain.interior_empty, 0u);
  uint32_t forced = 0, masked_out = 0;
  expect_plain_or_kept(plain, with, {}, kept, forced, masked_out);
  EXPECT_GT(forced, 0u);
}

TEST(OccupancyKept, TheMaskRulesOutAKeptCell) {
  Scene s;
  const uint32_t res = s.sizing.occupancy_resolution;
  const std::vector<uint32_t> mask = cells_every(res, 0, 2), interior = cells_every(res, 0, 5),
                              kept = cells_every(res, 0, 3);
  const Updated plain = update_once(s, mask, interior, {}), with = update_once(s, mask, interior, kept);
  uint32_t forced = 0, masked_out = 0;
  expect_plain_or_kept(plain, with, mask, kept, forced, masked_out);
  EXPECT_GT(masked_out, 0u);
}

}  // namespace
