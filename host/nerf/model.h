// The trained NeRF as one object: the field (hash grid + MLPs), the scene bounding box it covers,
// the occupancy grid used to skip empty space, the marching step, and how the model frame relates
// to the dataset frame. Snapshots (.lnerf, snapshot.h) are a small versioned JSON header followed by
// binary blobs with checksums; a newer or corrupt file is refused before anything is built, and
// saving is atomic (temporary file + rename).
//
// Conventions shared with the marcher (kernels/train/occupancy.h has the indexing rule):
//  - normalised position q = (p - aabb.min) / (aabb.max - aabb.min), the field's input in [0,1]^3;
//  - the occupancy grid has res^3 cells over [0,1)^3, cell x + res*(y + res*z), bit cell&31 of
//    word cell>>5; rays only take samples in occupied cells;
//  - samples are `step()` scene units apart along unit-length rays; the opacity of a sample is
//    1 - exp(-sigma * step) (sigma in 1/scene units); colours are linear RGB.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/runtime.h"
#include "host/field/field.h"
#include "host/nerf/snapshot.h"

namespace lorgnette::nerf {

class NerfModel {
 public:
  // A fresh model: field initialised from `seed`, every occupancy cell occupied. variant: the
  // field's kernels for the device (Auto) or forced (tests and benchmarks run the GPU ones on PoCL).
  NerfModel(cl::Runtime& rt, const field::FieldConfig& config, const Aabb& aabb, uint32_t occ_res, float step,
            uint32_t max_batch, uint64_t seed, bool deterministic,
            field::KernelVariant variant = field::KernelVariant::Auto);
  NerfModel(NerfModel&&) = default;
  NerfModel& operator=(NerfModel&&) = default;

  cl::Runtime& runtime() const { return *rt_; }
  field::Field& field() { return *field_; }
  const field::Field& field() const { return *field_; }
  const field::FieldConfig& field_config() const { return field_->config(); }
  const Aabb& aabb() const { return aabb_; }
  float step() const { return step_; }
  // Default cap on samples along one ray: the AABB diagonal in steps.
  uint32_t max_samples_per_ray() const;

  const OccupancyGrid& occupancy() const { return occ_; }
  uint32_t occupancy_resolution() const { return occ_.res; }
  const cl::Buffer<uint32_t>& occupancy_bits() const { return occ_bits_; }  // device bitfield
  // Replaces the grid (bits must have occ_word_count(res) words; density res^3 or empty).
  void set_occupancy(OccupancyGrid grid);

  SceneNormalisation normalisation;
  ModelMetadata metadata;
  // Where the training cameras looked from (view_range.h); empty for models saved before it was
  // recorded (render::model_view_range then measures it from the dataset when it can).
  std::optional<ViewRange> view_range;

  // Parameter count and bytes of the field (the model's size in memory and on disk, roughly).
  uint64_t param_bytes() const;

  // Writes the snapshot atomically. Throws std::runtime_error naming the path on failure.
  void save(const std::string& path) const;
  // Reads and validates the whole file first (magic, version, header, sizes, checksums) and throws
  // a clear std::runtime_error for a newer, truncated or corrupt file; builds nothing before that.
  static NerfModel load(cl::Runtime& rt, const std::string& path, uint32_t max_batch = 1u << 18,
                        bool deterministic = true);

 private:
  cl::Runtime* rt_;
  std::unique_ptr<field::Field> field_;
  Aabb aabb_;
  float step_;
  OccupancyGrid occ_;
  cl::Buffer<uint32_t> occ_bits_;
};

}  // namespace lorgnette::nerf
