// Resuming a training from its checkpoint (checkpoint.h) inside train_on_dataset: which checkpoint a
// training writes, the settings that identify it, and the restore with the log line "resuming at
// step N of M". `lorgnette train --resume` requires a matching checkpoint when one is there; the
// service's train stage takes one that matches and trains from step 0 (with a warning) otherwise.
#pragma once
#include <string>

#include "host/dataset/dataset.h"
#include "host/nerf/train_job.h"
#include "host/nerf/trainer.h"

namespace lorgnette::nerf {

// The checkpoint a training with `o` writes: o.checkpoint_path when given, else beside the snapshot
// (checkpoint_path_for); "" without either.
std::string checkpoint_for(const TrainOptions& o);

// The second training's checkpoint (train_on_dataset's retraining without the clearing).
std::string second_checkpoint(const std::string& checkpoint);

// Removes `checkpoint` and its second training's; nothing for "".
void remove_checkpoints(const std::string& checkpoint);

// The identity of the training `plan` runs on `ds` (CheckpointKey): the dataset's fingerprint and
// every setting a step depends on (model size and box, batch, budget, seed, optimiser, schedule,
// occupancy, room model, the occupancy mask), as JSON text.
CheckpointKey checkpoint_key(const dataset::Dataset& ds, const TrainPlan& plan, const TrainJob& job);

// Restores `trainer` from `o.checkpoint_path` according to `mode` (TrainJob::Resume); logs
// "resuming at step N of M" or why it starts at step 0. Throws CheckpointCorrupt or
// CheckpointMismatch in Required mode.
void resume_training(Trainer& trainer, const TrainOptions& o, TrainJob::Resume mode);

}  // namespace lorgnette::nerf
