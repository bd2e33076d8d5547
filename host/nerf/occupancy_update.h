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
  // A subject's certain interior (background_field.h solid_pull; a bitfield of the grid's cells, empty =
  // none): each update counts its cells that the density leaves unoccupied. The cells of `kept` (empty =
  // none; the interior's reach, which holds it) stay occupied whatever their density: the prior can
  // only pull on samples it is given, and it judges a ray's crossing of the reach by its samples there.
  void set_interior(std::vector<uint32_t> cells, std::vector<uint32_t> kept);
  // `grid` with its bits as its density alone gives them (update()'s rule without the kept cells): what
  // a saved model holds, since the kept cells serve the prior's crossing test in training only, and
  // renders and the fit read where the density is.
  OccupancyGrid without_kept(OccupancyGrid grid) const;
  // The interior's cells, and those the density left unoccupied at the last update.
  uint64_t interior_cells() const { return interior_count_; }
  uint64_t interior_empty() const { return interior_empty_; }
  uint32_t updates() const { return updates_; }
  // The update count seeds each update's jitter: a resumed training restores it (checkpoint.h).
  void set_updates(uint32_t n) { updates_ = n; }

 private:
  std::vector<uint32_t> pick_cells(uint32_t step) const;
  // The grid's bits from its density (rebuild_occupancy_bits at this grid's threshold, AND the mask).
  void density_bits(OccupancyGrid& grid) const;

  NerfModel& model_;
  OccupancyOptions options_;
  uint32_t seed_;
  std::vector<uint32_t> mask_, interior_, kept_;
  uint64_t interior_count_ = 0, interior_empty_ = 0;
  cl::Kernel points_k_;
  cl::Buffer<float> pos_, sigma_;
  cl::Buffer<uint32_t> cells_dev_;
  uint32_t updates_ = 0;
};

}  // namespace lorgnette::nerf
