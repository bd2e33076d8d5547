// Instant-NGP's occupancy grid maintenance: every few training steps the field's density is
// evaluated at one jittered point per cell (all cells during warm-up, afterwards the occupied
// cells plus a random quarter of the rest), folded into the per-cell estimate as an EMA
// (density = max(density * decay, new)), and cells whose density exceeds
// min(threshold_alpha / step, mean density) become occupied. An optional mask (e.g. the visual
// hull carved from alpha masks) is ANDed in: cells it rules out never become occupied.
#pragma once
#include <cstdint>
#include <vector>

#include "host/cl/kernel.h"
#include "host/nerf/model.h"

namespace lorgnette::nerf {

struct OccupancyOptions {
  uint32_t update_every = 16;   // training steps between updates
  uint32_t warmup_steps = 256;  // until then every cell is evaluated at every update
  float decay = 0.95f;
  float threshold_alpha = 0.01f;  // opacity of one step that counts as occupied
};

// grid.density[c] = max(grid.density[c] * decay, sigma[i]) for the listed cells, decay elsewhere.
void fold_occupancy(OccupancyGrid& grid, const std::vector<uint32_t>& cells, const std::vector<float>& sigma,
                    float decay);
// Bits from densities: density > min(threshold, mean), AND mask (when not empty).
void rebuild_occupancy_bits(OccupancyGrid& grid, float threshold, const std::vector<uint32_t>& mask);

class OccupancyUpdater {
 public:
  OccupancyUpdater(NerfModel& model, const OccupancyOptions& options, uint32_t seed,
                   std::vector<uint32_t> mask = {});
  // Call after every training step; updates when step % update_every == 0.
  void maybe_update(uint32_t step);
  void update(uint32_t step);
  // Cells that stay occupied whatever their density (a subject's certain interior, background_field.h
  // solid_pull: the prior can only pull on samples it is given); empty = none.
  void set_forced(std::vector<uint32_t> forced);
  uint32_t updates() const { return updates_; }

 private:
  std::vector<uint32_t> pick_cells(uint32_t step) const;

  NerfModel& model_;
  OccupancyOptions options_;
  uint32_t seed_;
  std::vector<uint32_t> mask_, forced_;
  cl::Kernel points_k_;
  cl::Buffer<float> pos_, sigma_;
  cl::Buffer<uint32_t> cells_dev_;
  uint32_t updates_ = 0;
};

}  // namespace lorgnette::nerf
