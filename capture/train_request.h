// The training request from its settings to a loaded dataset and a ready TrainJob: the settings
// checked (nerf::validate, host/util/bounds.h) before anything is read, the training split loaded,
// and the subject box applied (the --aabb override, else --box / --hair / --no-masks through
// apply_subject_box). `lorgnette train` and Python's train() both start here; the demo, which
// trains on its own synthetic dataset in the dataset's box, uses nerf::train_job alone.
#pragma once
#include "host/dataset/dataset.h"
#include "host/nerf/train_job.h"
#include "host/nerf/train_settings.h"

namespace lorgnette::capture {

struct TrainRequest {
  dataset::Dataset dataset;  // the training split (TrainJob's views point into it)
  nerf::TrainJob job;
};

// Throws OutOfRange or std::invalid_argument for bad settings (before the dataset is read), and
// what load_dataset and apply_subject_box throw.
TrainRequest prepare_training(const std::string& dataset_path, const nerf::TrainSettings& settings);

}  // namespace lorgnette::capture
