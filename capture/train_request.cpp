// Settings -> dataset + TrainJob with the subject box applied (train_request.h).
#include "capture/train_request.h"

#include <spdlog/spdlog.h>

#include "capture/subject_box.h"

namespace lorgnette::capture {

TrainRequest prepare_training(const std::string& dataset_path, const nerf::TrainSettings& settings) {
  nerf::validate(settings);
  BoxSource source = box_source_from_string(settings.box);  // a bad name fails before the load
  TrainRequest r;
  r.job = nerf::train_job(settings);
  r.dataset = dataset::load_dataset(dataset_path, nerf::train_load_options(settings));
  spdlog::info("dataset: {} ({}), {} frames", dataset_path, r.dataset.format, r.dataset.frames.size());
  if (r.job.sizing.aabb) {
    spdlog::info("subject box: --aabb (given on the command line)");
    return r;
  }
  fit::HeadBoxOptions head;
  if (settings.hair_mm) head.extents.hair_mm = *settings.hair_mm;
  apply_subject_box(r.dataset, source, settings.masks, r.job, head);
  return r;
}

}  // namespace lorgnette::capture
