// The training checkpoint (.ckpt, docs/file-formats.md): everything the next training step depends
// on, so a training killed or interrupted continues where it stopped and takes the steps it would
// have taken. A .lnerf snapshot holds only what renders (parameters and occupancy); a checkpoint adds
// Adam's moments and step count, the occupancy density and its update count (the jitter's seed), the
// ray-count adaptation, the step and sample counters, the elapsed time of the schedule, and the same
// for the room model (background_field.h). All randomness is counter-based on (seed, step), so the
// step and those counters are the random state.
//
// A checkpoint belongs to one training: the dataset's fingerprint and the training's settings
// (CheckpointKey) are stored and compared whole; another dataset or other settings are refused with
// a message naming what differs. Written atomically (write_file_atomic): a kill while it is written
// leaves the previous checkpoint.
#pragma once
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "host/field/field.h"
#include "host/nerf/snapshot.h"

namespace lorgnette::nerf {

inline constexpr uint32_t kCheckpointVersion = 1;

// One field's training state: parameters, Adam, occupancy grid (bits and density) and its updater.
struct FieldState {
  std::vector<float> params;
  field::OptimiserState adam;
  OccupancyGrid occupancy;
  uint32_t occupancy_updates = 0;
};

struct TrainingState {
  uint64_t step = 0, samples = 0, rays = 0;
  uint32_t n_rays = 0;     // the next step's ray count (adapted with integer arithmetic)
  double elapsed = 0.0;    // training seconds so far (the schedule of a --seconds budget)
  double last_loss = 0.0;  // the last known step loss (the model's final_loss when nothing is left)
  FieldState subject;
  std::optional<FieldState> room;  // with a room model
  uint64_t room_samples = 0;
};

// What a checkpoint continues: the dataset's fingerprint (dataset_fingerprint) and the training's
// settings as JSON text (the model's size, batch, budget, seed, optimiser, schedule, room model).
struct CheckpointKey {
  std::string dataset_hash;
  std::string settings;
};

// Not a checkpoint, or a damaged one (truncated, a checksum that does not match, a bad value).
class CheckpointCorrupt : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
// A valid checkpoint of another training (dataset or settings).
class CheckpointMismatch : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The checkpoint beside a model file: MODEL.ckpt.
std::string checkpoint_path_for(const std::string& model_path);

std::string encode_checkpoint(const CheckpointKey& key, const TrainingState& state);
// Parses and checks a whole checkpoint (magic, version, header checksum, blob sizes and checksums,
// finite values); throws CheckpointCorrupt naming `path` and what is wrong. The key is returned in
// `key` for check_checkpoint_key.
TrainingState parse_checkpoint(std::string_view bytes, const std::string& path, CheckpointKey& key);
// Throws CheckpointMismatch unless `found` is `want`, naming the dataset or the settings that differ.
void check_checkpoint_key(const CheckpointKey& want, const CheckpointKey& found, const std::string& path);

void write_checkpoint(const std::string& path, const CheckpointKey& key, const TrainingState& state);
// nullopt when no file is at `path`; else the checked state of the training `key` (throws as above).
std::optional<TrainingState> read_checkpoint(const std::string& path, const CheckpointKey& key);

}  // namespace lorgnette::nerf
