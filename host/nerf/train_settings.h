// The training request as a user states it (the `lorgnette train` flags, Python's train() arguments,
// the demo's training stage), with the CLI's defaults, and the one place its numbers are checked
// against host/util/bounds.h: train_load_options() and train_job() turn it into the dataset's
// LoadOptions and the TrainJob (train_job.h), so every front end trains alike and refuses alike. The
// subject box (box, hair_mm, masks) needs the loaded dataset: capture/train_request.h applies it.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "host/dataset/dataset.h"
#include "host/nerf/background_field.h"
#include "host/nerf/train_job.h"

namespace lorgnette::nerf {

struct TrainSettings {
  std::string output;             // the snapshot (.lnerf): at the end, on Ctrl-C and every snapshot_every
  std::optional<uint64_t> steps;  // neither steps nor seconds: the size-based budget (train_budget.h)
  std::optional<double> seconds;
  uint32_t seed = 1337;
  uint32_t batch_log2 = 0;  // 0: by device (sizing.h)
  bool deterministic = false, linear_loss = false, progress = true;
  std::string background = "auto";  // room model: auto | on | off
  // The subject box (capture/subject_box.h): auto | dataset | masks | head | cameras; `aabb` overrides.
  std::string box = "auto";
  bool masks = true;              // let the sizing carve the alpha-mask hull (--no-masks: false)
  std::optional<double> hair_mm;  // the head box's hair allowance; absent: fit::HeadExtents' default
  // The model's size: absent or 0 = chosen from the data (sizing.h).
  std::optional<Aabb> aabb;
  float aabb_scale = 0.0f, step = 0.0f;
  uint32_t finest_res = 0, log2_table = 0, levels = 0, occ_res = 0;
  float lr = 1e-2f;
  double snapshot_every = 120.0;  // seconds; 0: only at the end
  // Continue from the training checkpoint beside the output (OUTPUT.ckpt) when there is one
  // (train_resume.h); a corrupt one or one of another training is refused.
  bool resume = false;
  BackgroundOptions room;                // the room model's prior and clearing weights
  uint32_t downscale = 1, max_side = 0;  // image loading; max_side 0: no limit
};

// Throws OutOfRange (bounds.h), naming the flag and Python's argument, for any number outside its
// range, and std::invalid_argument for a bad name or steps given with seconds.
void validate(const TrainSettings& settings);

// Throws when the model file `output` would be written over a file of the dataset `data` (the
// descriptor itself, or a JSON file in the dataset's folder), even with --force.
void refuse_output_onto_dataset(const std::string& output, const std::string& data);

// Throws unless the training may write its model and checkpoint (checkpoint.h): an existing model is
// overwritten only with `force`, or by `resume` when its training's checkpoint is beside it (the
// model is that training's snapshot); a checkpoint there is an unfinished training, never written
// over without `resume` or `force`. `force_flag` and `resume_flag` name the front end's flags in the
// messages ("--force", "force=True").
void refuse_overwrite(const TrainSettings& settings, bool force, const std::string& force_flag,
                      const std::string& resume_flag);

// The training split's LoadOptions (downscale, max_side, the kTrainImageBytes cap). Validates.
dataset::LoadOptions train_load_options(const TrainSettings& settings);

// The TrainJob of `settings` (the box override, sizing overrides, the trainer's options). Validates.
TrainJob train_job(const TrainSettings& settings);

// "minx,miny,minz,maxx,maxy,maxz" -> a box within bounds::kAabbCoord with max > min; nullopt for "".
std::optional<Aabb> parse_aabb(const std::string& text);

}  // namespace lorgnette::nerf
