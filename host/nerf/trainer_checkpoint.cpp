// Trainer's checkpoint seam (checkpoint.h): the state the next step depends on, read from the
// devices, and its restoration before run(). Kept apart from the step and the loop (trainer.cpp).
#include <spdlog/spdlog.h>

#include <filesystem>

#include "host/nerf/trainer.h"

namespace lorgnette::nerf {
namespace {

FieldState field_state(const NerfModel& model, const OccupancyUpdater& occupancy) {
  return {model.field().download_params(), model.field().download_optimiser(), model.occupancy(),
          occupancy.updates()};
}

void restore_field(NerfModel& model, OccupancyUpdater& occupancy, const FieldState& s, const char* what) {
  if (s.occupancy.res != model.occupancy_resolution())
    throw CheckpointMismatch(std::string("the checkpoint's ") + what + " has another occupancy resolution");
  model.field().restore(s.params, s.adam);
  model.set_occupancy(s.occupancy);
  occupancy.set_updates(s.occupancy_updates);
}

}  // namespace

TrainingState Trainer::state() const {
  TrainingState s;
  s.step = step_;
  s.samples = samples_;
  s.rays = rays_;
  s.n_rays = n_rays_;
  s.elapsed = elapsed_;
  s.last_loss = last_loss_;
  s.subject = field_state(model_, *occupancy_);
  if (background_) {
    s.room = field_state(background_->model(), background_->occupancy_updater());
    s.room_samples = background_->samples_done();
  }
  return s;
}

void Trainer::restore(const TrainingState& s) {
  if (s.room.has_value() != bool(background_))
    throw CheckpointMismatch(background_ ? "the checkpoint has no room model but this training has one"
                                         : "the checkpoint has a room model but this training has none");
  try {
    restore_field(model_, *occupancy_, s.subject, "model");
    if (background_) {
      restore_field(background_->model(), background_->occupancy_updater(), *s.room, "room model");
      background_->set_samples_done(s.room_samples);
    }
  } catch (const std::invalid_argument& e) {  // a size the settings check let through
    throw CheckpointMismatch(std::string("the checkpoint does not fit this model: ") + e.what());
  }
  step_ = s.step;
  samples_ = s.samples;
  rays_ = s.rays;
  n_rays_ = s.n_rays;
  elapsed_ = resumed_elapsed_ = s.elapsed;
  last_loss_ = s.last_loss;
  pending_ = PendingLoss::None;
  good_params_.clear();  // the divergence copy is taken again from here
  good_step_ = step_;
}

void Trainer::save_checkpoint(double elapsed) {
  if (options_.checkpoint_path.empty() || step_ == 0) return;
  elapsed_ = elapsed;
  write_checkpoint(options_.checkpoint_path, options_.checkpoint_key, state());
}

}  // namespace lorgnette::nerf
