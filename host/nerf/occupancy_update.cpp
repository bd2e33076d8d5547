// OccupancyUpdater: the device evaluates densities at jittered cell points; the host folds them into
// the grid in cell order (deterministic) and uploads the new bitfield.
#include "host/nerf/occupancy_update.h"

#include <algorithm>
#include <cmath>

#include "host/nerf/subject_volume.h"
#include "kernels/train/occupancy.h"
#include "kernels/train/train_types.h"

namespace lorgnette::nerf {

void fold_occupancy(OccupancyGrid& grid, const std::vector<uint32_t>& cells, const std::vector<float>& sigma,
                    float decay) {
  size_t n_cells = size_t(grid.res) * grid.res * grid.res;
  if (grid.density.size() != n_cells) grid.density.assign(n_cells, 0.0f);
  for (float& d : grid.density) d *= decay;
  for (size_t i = 0; i < cells.size(); ++i) {
    float s = std::isfinite(sigma[i]) ? sigma[i] : 0.0f;
    grid.density[cells[i]] = std::max(grid.density[cells[i]], s);
  }
}

void rebuild_occupancy_bits(OccupancyGrid& grid, float threshold, const std::vector<uint32_t>& mask) {
  double sum = 0.0;
  for (float d : grid.density) sum += d;
  float mean = grid.density.empty() ? 0.0f : float(sum / double(grid.density.size()));
  float thr = std::min(threshold, mean);
  grid.bits.assign(occ_word_count(grid.res), 0u);
  for (size_t c = 0; c < grid.density.size(); ++c)
    if (grid.density[c] > thr) grid.bits[c >> 5] |= 1u << (c & 31u);
  if (!mask.empty())
    for (size_t w = 0; w < grid.bits.size(); ++w) grid.bits[w] &= mask[w];
}

OccupancyUpdater::OccupancyUpdater(NerfModel& model, const OccupancyOptions& options, uint32_t seed,
                                   std::vector<uint32_t> mask)
    : model_(model), options_(options), seed_(seed), mask_(std::move(mask)) {
  cl::Runtime& rt = model.runtime();
  points_k_ = cl::Kernel(rt.program("train/occupancy.cl"), "occupancy_points");
  uint32_t batch = model.field().max_batch();
  pos_ = cl::Buffer<float>(rt, size_t(batch) * 3);
  sigma_ = cl::Buffer<float>(rt, batch);
  uint32_t res = model.occupancy_resolution();
  cells_dev_ = cl::Buffer<uint32_t>(rt, size_t(res) * res * res);
}

std::vector<uint32_t> OccupancyUpdater::pick_cells(uint32_t step) const {
  const OccupancyGrid& g = model_.occupancy();
  uint32_t n_cells = g.res * g.res * g.res;
  bool all = step < options_.warmup_steps || g.density.empty();
  std::vector<uint32_t> cells;
  cells.reserve(n_cells);
  for (uint32_t c = 0; c < n_cells; ++c) {
    if (!mask_.empty() && !((mask_[c >> 5] >> (c & 31u)) & 1u)) continue;  // ruled out for good
    bool occupied = (g.bits[c >> 5] >> (c & 31u)) & 1u;
    if (all || occupied || (lgn_hash3(seed_, step, c) & 3u) == 0u) cells.push_back(c);
  }
  return cells;
}

void OccupancyUpdater::update(uint32_t step) {
  cl::Runtime& rt = model_.runtime();
  std::vector<uint32_t> cells = pick_cells(step);
  std::vector<float> sigma(cells.size());
  if (!cells.empty()) cells_dev_.write(rt, cells);
  uint32_t batch = model_.field().max_batch();
  for (uint32_t first = 0; first < cells.size(); first += batch) {
    uint32_t n = std::min<uint32_t>(batch, static_cast<uint32_t>(cells.size()) - first);
    OccParams p{model_.occupancy_resolution(), first, n, batch, seed_, updates_, 0, 0};
    points_k_.args(p, cells_dev_, pos_).launch(rt, n, 64);
    model_.field().density(pos_, n, sigma_);
    sigma_.read(rt, sigma.data() + first, n);
  }
  OccupancyGrid grid = model_.occupancy();
  fold_occupancy(grid, cells, sigma, options_.decay);
  density_bits(grid);
  if (interior_.size() == grid.bits.size()) {
    interior_empty_ = 0;
    for (size_t w = 0; w < grid.bits.size(); ++w)
      interior_empty_ +=
          uint64_t(__builtin_popcount(interior_[w] & (mask_.empty() ? ~0u : mask_[w]) & ~grid.bits[w]));
  }
  if (kept_.size() == grid.bits.size())
    for (size_t w = 0; w < grid.bits.size(); ++w) grid.bits[w] |= kept_[w];
  model_.set_occupancy(std::move(grid));
  ++updates_;
}

void OccupancyUpdater::set_interior(std::vector<uint32_t> cells, std::vector<uint32_t> kept) {
  interior_ = std::move(cells);
  kept_ = std::move(kept);
  if (!mask_.empty() && kept_.size() == mask_.size())  // a cell the mask rules out is never kept
    for (size_t w = 0; w < kept_.size(); ++w) kept_[w] &= mask_[w];
  interior_count_ = mask_count(interior_);
}

void OccupancyUpdater::density_bits(OccupancyGrid& grid) const {
  rebuild_occupancy_bits(grid, options_.threshold_alpha / model_.step(), mask_);
}

OccupancyGrid OccupancyUpdater::without_kept(OccupancyGrid grid) const {
  if (kept_.empty() || grid.density.empty()) return grid;
  density_bits(grid);
  return grid;
}

void OccupancyUpdater::maybe_update(uint32_t step) {
  if (step % options_.update_every == 0) update(step);
}

}  // namespace lorgnette::nerf
