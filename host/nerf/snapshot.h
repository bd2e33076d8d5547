// The NeRF model as plain host data (bounding box, scene normalisation, metadata, occupancy grid,
// parameters) and its .lnerf snapshot format, with no OpenCL: NerfModel (model.h) saves and loads
// through these functions, and the fuzzers parse snapshots without a device.
//
// Format: 8 bytes magic "LGNNERF\n", 8 bytes little-endian header length H, H bytes of JSON header,
// then the binary blobs the header lists (name, offset from the end of the header, bytes, FNV-1a 64
// checksum). From version 2 the header carries its own checksum, "header_fnv1a64": FNV-1a 64 of the
// header's H bytes with that value's 16 hex digits read as '0', so a flipped bit in the box, the step
// or the normalisation is refused like one in a blob. Version 1 files (no header checksum) still load.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "host/field/field_config.h"
#include "host/nerf/view_range.h"

namespace lorgnette::nerf {

constexpr uint32_t kSnapshotVersion = 2;
// The header key of the header checksum (version 2 on).
inline constexpr const char* kHeaderChecksumKey = "header_fnv1a64";

struct Aabb {
  std::array<float, 3> min{0.0f, 0.0f, 0.0f}, max{1.0f, 1.0f, 1.0f};
  float extent(int axis) const { return max[axis] - min[axis]; }
  float max_extent() const;
  float diagonal() const;
  std::array<float, 3> center() const;
  bool valid() const;  // finite and max > min on every axis
  std::array<float, 3> normalise(const std::array<float, 3>& p) const;
};

// model frame = dataset frame * scale + offset (identity unless the trainer says otherwise), so
// every output can be mapped back to the dataset's cameras.
struct SceneNormalisation {
  float scale = 1.0f;
  std::array<float, 3> offset{0.0f, 0.0f, 0.0f};
};

// A metric scale the capture measured (a card held to the face, triangulated): millimetres per scene
// unit of this model with its 1-sigma uncertainty.
struct CaptureMetricScale {
  std::string source = "card";
  double mm_per_unit = 0.0, mm_per_unit_uncertainty = 0.0;
};

struct ModelMetadata {
  uint64_t steps = 0;
  double train_seconds = 0.0;
  uint64_t samples_trained = 0;
  uint64_t seed = 0;
  float final_loss = 0.0f;  // NaN when training diverged (written as JSON null)
  std::string dataset_path, dataset_hash, device, created;
  // Why the subject could not be separated from the room, with what to film differently ("" when it
  // was): the fit then never passes this model as good.
  std::string subject_problem;
  // The product's check of its own output (subject_holes.h): the share of the face's and neck's rays
  // from the training views that are transparent, over all views and in the worst one; -1 when not
  // checked (no face region known, or no room model).
  double holes = -1.0, holes_worst_view = -1.0;
  // "metric_scale" (optional): absent when the capture measured none; the fit then estimates the
  // scale from the irises or the mean face (fit/scale_chain.h).
  std::optional<CaptureMetricScale> metric_scale;
};

// Occupancy grid state: per-cell density estimate (EMA; empty until training updates it) and the
// bitfield derived from it (all cells occupied in a fresh model).
struct OccupancyGrid {
  uint32_t res = 64;
  std::vector<float> density;  // res^3 or empty
  std::vector<uint32_t> bits;  // occ_word_count(res)
  uint64_t occupied_count() const;
  double occupied_fraction() const;
};

// The full-grid occupancy bitfield of a fresh model.
OccupancyGrid full_occupancy(uint32_t res);

// Everything a snapshot file holds.
struct Snapshot {
  field::FieldConfig config;
  Aabb aabb;
  float step = 0.0f;
  OccupancyGrid occ;
  std::vector<float> params;  // config.param_count() values
  SceneNormalisation normalisation;
  ModelMetadata metadata;
  // The directions the training cameras looked from (model frame); absent in files written before
  // it was recorded (version 1 files without "view_range" still load).
  std::optional<ViewRange> view_range;
};

// The bytes of a snapshot file.
std::string encode_snapshot(const Snapshot& s);
// FNV-1a 64 of `bytes`: the blobs' checksum and the header's.
uint64_t snapshot_checksum(std::string_view bytes);
// `header` (JSON text holding "header_fnv1a64": "<16 hex digits>") with those digits set to the
// header's checksum; returned unchanged when it holds no such key. The writer seals every header;
// tests and the header fuzzer seal the headers they edit.
std::string seal_header(std::string header);
// Parses and validates a whole snapshot file (magic, version, header and its checksum, sizes, blob
// checksums, finite values, and the numbers' ranges: host/util/bounds.h); throws a clear
// std::runtime_error naming `path` for a newer, truncated or corrupt one.
Snapshot parse_snapshot(std::string_view bytes, const std::string& path);
// Reads `path` and parses it; also throws when the file cannot be opened or is not a regular file
// (a FIFO would block the reader).
Snapshot read_snapshot(const std::string& path);

}  // namespace lorgnette::nerf
