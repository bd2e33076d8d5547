// Training a model from a loaded dataset in one call: the training views, the automatic model size
// (with the caller's overrides), a fresh NerfModel on the runtime, its metadata (dataset path and
// fingerprint, device) and the Trainer run. `lorgnette train` and the demo both go through here.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "host/dataset/dataset.h"
#include "host/nerf/model.h"
#include "host/nerf/sizing.h"
#include "host/nerf/subject_volume.h"
#include "host/nerf/train_budget.h"
#include "host/nerf/trainer.h"

namespace lorgnette::nerf {

// The most image memory a training loads (dataset::LoadOptions::max_image_bytes for `lorgnette train`
// and Python's train): the training views go to the device in one buffer, and PoCL on the team's
// machines allocates at most 2 GiB at once. 1.5 GB is ~94 M pixels: 45 full 1080p frames, or 300
// at about 0.55x, more than a head model trained in minutes resolves (docs/bench/dataset.md).
inline constexpr uint64_t kTrainImageBytes = 1'500'000'000;

struct TrainJob {
  SizingOverrides sizing;   // its aabb_scale is replaced by `aabb_scale` below
  float aabb_scale = 0.0f;  // box size factor for mask-less datasets; 0 = the dataset's own hint
  uint32_t batch_log2 = 0;  // samples per step = 2^batch_log2; 0: device_batch_log2 (sizing.h)
  bool deterministic = false;
  // Room model behind the subject (background_field.h) and the subject's connected region after
  // training (subject_region.h): "auto" = on for mask-less datasets whose box is not the cameras'.
  std::string background = "auto";  // auto | on | off
  // The subject's volume inside its box when known (the head's volume from the landmark head box,
  // capture/head_volume.h). With a room model it becomes a permanent occupancy mask of the subject
  // (subject_volume.h), and the room model's cutout: the box's corners and the space around the head
  // outside it never hold subject density and belong to the room model. Ignored without a room model.
  // Its keep and core zones go to the clearing (BackgroundOptions::subject).
  std::optional<SubjectZones> subject;
  TrainOptions train;  // steps/seconds (both 0: the size-based default, train_budget.h), seed, ...
  // Why the subject could not be separated (capture/subject_box.h), kept in the model's metadata;
  // training adds its own reason when the room model finds no subject region.
  std::string subject_problem;
  // When the trained head has holes in its face or neck (subject_holes.h), train once more without
  // the room-explained clearing and keep that model when it is whole; holes that remain become the
  // model's subject_problem (on the first model, which keeps the clearing's cleaner room).
  bool retrain_on_holes = true;
  // The training checkpoint (checkpoint.h, train_resume.h) at train.checkpoint_path, or beside the
  // snapshot: Off trains from step 0 (writing over it); Required (train --resume) continues from it
  // when it is there and refuses one that is corrupt or of another training; IfValid (the service)
  // continues from a matching one and trains from step 0, with a warning, otherwise.
  enum class Resume { Off, IfValid, Required } resume = Resume::Off;
  // The checkpoints stay when the training completes: the caller removes them once the model is in
  // place (the service's stage, after its rename). Otherwise they go when the model is complete.
  bool keep_checkpoint = false;
  // Called once with the step budget the plan chose (train_budget.h), before the first step: a
  // caller that gave no step count learns the total its progress is a share of (0: a time budget).
  std::function<void(uint64_t steps)> on_planned;
};

struct TrainJobResult {
  NerfModel model;
  ModelSizing sizing;
  TrainResult result;
  std::string budget;       // which budget applied and why (train_budget.h)
  bool background = false;  // trained with a room model
  std::string region;       // the subject region's summary ("" without a room model)
};

// The training split's views (pointers into `ds`, which must outlive them). Throws a clear error
// when the dataset has no training frames.
std::vector<View> training_views(const dataset::Dataset& ds);

// A short fingerprint of the dataset's frames (paths and poses) for the snapshot header.
std::string dataset_fingerprint(const dataset::Dataset& ds);

// The directions `views` looked from about the centre of `box` (model frame: the views' positions
// mapped through `normalisation`), for the snapshot.
ViewRange training_view_range(const std::vector<View>& views, const Aabb& box,
                              const SceneNormalisation& normalisation = {});

// What train_on_dataset decides before the first step, logged as it goes: the model's size (a room
// capture's table cap and the subject volume's occupancy mask applied), the batch, whether a room
// model runs and the step budget. Benchmarks build their arms from it, so they train what `train`
// trains.
struct TrainPlan {
  ModelSizing sizing;
  TrainOptions train;  // the job's, with the budget's steps when it gave none and the room model's flags
  uint32_t batch_log2 = 16;
  bool background = false;  // a room model runs
  std::string budget;       // which budget applied and why (train_budget.h)
};
TrainPlan plan_training(cl::Runtime& rt, const dataset::Dataset& ds, const std::vector<View>& views,
                        TrainJob job);

// The dataset's scale.json (host/dataset/metric_scale.h) in the model's units: model = dataset *
// normalisation.scale, so millimetres per model unit are those per dataset unit over that scale (the
// uncertainty alike). nullopt without a scale.json; a malformed one throws (its message says so).
std::optional<MetricScale> model_metric_scale(const dataset::Dataset& ds, const SceneNormalisation& n);

// A fresh model of `plan`'s size with the dataset's metadata (path, fingerprint, device, captured
// directions; the job's subject problem) and its coverage advice logged.
NerfModel planned_model(cl::Runtime& rt, const dataset::Dataset& ds, const std::vector<View>& views,
                        const TrainPlan& plan, const TrainJob& job);

// Sizes, builds and trains a model on `ds`'s training split; logs the chosen size.
TrainJobResult train_on_dataset(cl::Runtime& rt, const dataset::Dataset& ds, TrainJob job);

}  // namespace lorgnette::nerf
