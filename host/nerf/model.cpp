// NerfModel: construction, occupancy upload, and saving/loading through the .lnerf snapshot format
// (snapshot.h), which is validated in full before any device object is built.
#include "host/nerf/model.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "host/util/bounds.h"
#include "host/util/image_io.h"
#include "kernels/train/occupancy.h"

namespace lorgnette::nerf {

NerfModel::NerfModel(cl::Runtime& rt, const field::FieldConfig& config, const Aabb& aabb, uint32_t occ_res,
                     float step, uint32_t max_batch, uint64_t seed, bool deterministic,
                     field::KernelVariant variant)
    : rt_(&rt),
      field_(std::make_unique<field::Field>(rt, config, max_batch, seed, deterministic, variant)),
      aabb_(aabb),
      step_(step) {
  if (!aabb.valid())
    throw std::invalid_argument("NerfModel: the bounding box must have max > min on every axis");
  if (!(step > 0.0f)) throw std::invalid_argument("NerfModel: the step size must be positive");
  check_steps_per_diagonal(aabb.diagonal(), step, "the model's marching step (train --step)");
  if (occ_res < 1 || occ_res > 1024)
    throw std::invalid_argument(
        fmt::format("NerfModel: occupancy resolution {} is outside 1..1024", occ_res));
  set_occupancy(full_occupancy(occ_res));
}

uint32_t NerfModel::max_samples_per_ray() const {
  return static_cast<uint32_t>(std::ceil(aabb_.diagonal() / step_)) + 1u;
}

void NerfModel::set_occupancy(OccupancyGrid grid) {
  uint64_t cells = uint64_t(grid.res) * grid.res * grid.res;
  if (grid.bits.size() != occ_word_count(grid.res) || (!grid.density.empty() && grid.density.size() != cells))
    throw std::invalid_argument(fmt::format("occupancy grid of resolution {} needs {} words ({} given)",
                                            grid.res, occ_word_count(grid.res), grid.bits.size()));
  if (occ_bits_.size() != grid.bits.size()) occ_bits_ = cl::Buffer<uint32_t>(*rt_, grid.bits.size());
  occ_bits_.write(*rt_, grid.bits);
  occ_ = std::move(grid);
}

uint64_t NerfModel::param_bytes() const { return field_->config().bytes(); }

void NerfModel::save(const std::string& path) const {
  Snapshot s;
  s.config = field_->config();
  s.aabb = aabb_;
  s.step = step_;
  s.occ = occ_;
  s.params = field_->download_params();
  s.normalisation = normalisation;
  s.metadata = metadata;
  s.view_range = view_range;
  write_text_file_atomic(path, encode_snapshot(s));
}

NerfModel NerfModel::load(cl::Runtime& rt, const std::string& path, uint32_t max_batch, bool deterministic) {
  Snapshot s = read_snapshot(path);
  NerfModel m(rt, s.config, s.aabb, s.occ.res, s.step, max_batch, s.metadata.seed, deterministic);
  m.field_->upload_params(s.params);
  m.set_occupancy(std::move(s.occ));
  m.normalisation = s.normalisation;
  m.metadata = std::move(s.metadata);
  m.view_range = s.view_range;
  return m;
}

}  // namespace lorgnette::nerf
