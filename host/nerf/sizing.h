// "A model no more than the scene needs": derives the bounding box, the finest hash-grid
// resolution, the hash-table size, the occupancy resolution and the marching step from the
// training views, and reports the choice with its size in MB. Every value can be overridden.
//
//  - Look-at point: the least-squares point closest to all cameras' optical axes.
//  - AABB: with alpha masks, the bounds of the visual hull carved on a 64^3 grid around the
//    cube of half the nearest camera distance around the look-at point (a cell survives when half
//    of the views see it and, in every view that sees it, the mask dilated by the cell's
//    projected size covers it), dilated by one cell; the same hull becomes a
//    permanent occupancy mask. Without masks: a cube around the look-at point with half-size
//    aabb_scale * 0.5 * (median camera distance to the look-at point).
//  - Finest resolution: the AABB's largest extent divided by the pixel footprint at the nearest
//    camera distance to the box (a finer grid cannot be constrained by any pixel).
//  - Hash table: 2^ceil(log2(cells near the surface at the finest level)), within 2^14..2^19,
//    where surface cells = carved boundary area / finest cell area.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "host/field/field_config.h"
#include "host/nerf/model.h"
#include "host/nerf/views.h"

namespace lorgnette::nerf {

struct SizingOverrides {
  std::optional<Aabb> aabb;
  std::optional<uint32_t> finest_resolution, log2_table_size, levels, occupancy_resolution;
  std::optional<float> step;          // scene units
  float aabb_scale = 1.0f;            // dataset hint (no-mask datasets)
  uint32_t steps_per_diagonal = 512;  // default step = AABB diagonal / this
  bool use_masks = true;              // carve the visual hull from alpha when present
};

struct ModelSizing {
  Aabb aabb;
  field::FieldConfig field;
  uint32_t occupancy_resolution = 64;
  float step = 0.0f;
  std::vector<uint32_t> occupancy_mask;  // occ_word_count(res) words, or empty (no masks)
  std::array<float, 3> look_at{0, 0, 0};
  double nearest_distance = 0.0, pixel_footprint = 0.0;
  std::string from;  // "alpha masks (visual hull)" or "cameras (aabb_scale)" or "override"
  double megabytes() const { return double(field.bytes()) / (1024.0 * 1024.0); }
  std::string summary() const;  // one paragraph: each value and why
};

// Samples per training step for a device, as log2: 18 on a GPU (Instant-NGP's 2^18 per step; a
// GPU needs that many samples in flight to fill its cores), 16 otherwise (on PoCL a 2^16 step
// already gives every thread hundreds of work-groups, and smaller steps mean more steps per second).
uint32_t device_batch_log2(const cl::DeviceInfo& device);

// views: training views with images (alpha used when the images have any alpha < 1).
ModelSizing choose_model_size(const std::vector<View>& views, const SizingOverrides& overrides);

// The least-squares point nearest to all optical axes (falls back to the camera centroid when the
// axes are (nearly) parallel).
std::array<float, 3> cameras_look_at(const std::vector<Camera>& cameras);

}  // namespace lorgnette::nerf
