// The training loop: per step, random rays over all training pixels -> samples in occupied cells
// (RayBatch) -> Field::forward -> volume-rendering loss and its gradient -> Field::backward ->
// Adam, with occupancy-grid updates every few steps, a learning-rate schedule, a progress bar,
// periodic snapshots, Ctrl-C (stop and keep the model) and divergence handling (a NaN/inf loss
// restores the last good parameters, saves them as the snapshot and throws TrainingDiverged).
// Deterministic mode: same seed + same device -> bitwise the same loss curve and model (all
// randomness is counter-based; every reduction has a fixed order; ray counts adapt with integer
// arithmetic only).
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/field/field_config.h"
#include "host/nerf/background_field.h"
#include "host/nerf/checkpoint.h"
#include "host/nerf/model.h"
#include "host/nerf/occupancy_update.h"
#include "host/nerf/ray_batch.h"
#include "host/nerf/views.h"
#include "kernels/train/train_types.h"

namespace lorgnette {
class Progress;
}

namespace lorgnette::nerf {

struct TrainOptions {
  uint64_t steps = 0;    // stop after this many steps (0: no step limit)
  double seconds = 0.0;  // stop after this much time (0: no time limit); one of the two is required
  uint32_t seed = 1337;
  uint32_t loss_kind = LOSS_L2_SRGB;
  field::AdamConfig adam;  // lr is the base learning rate
  // Learning rate: base until `decay_start` of the run (steps or seconds), then exponential decay
  // to base * final_lr_fraction at the end.
  double decay_start = 0.5, final_lr_fraction = 0.1;
  OccupancyOptions occupancy;
  BackgroundOptions background;  // a room model behind the subject (mask-less captures)
  std::string snapshot_path;     // periodic / final / last-good snapshots ("" = none)
  double snapshot_every_seconds = 120.0;
  // The training checkpoint (checkpoint.h), written with every snapshot and at the end ("" = none),
  // and the training it belongs to.
  std::string checkpoint_path;
  CheckpointKey checkpoint_key;
  uint32_t good_copy_every = 50;  // steps between in-memory copies of the parameters for NaN recovery
  bool progress = true;
  // Called once per step with (steps done, seconds, that step's loss); for benchmarks, tests and
  // Python's progress hook. Without a room model a step's loss arrives with the next step's
  // synchronisation, so the call comes after the next step was issued (the last one after the loop).
  std::function<void(uint64_t, double, double)> on_step;
  // Read each step's loss right after the step (one more synchronisation per step), so on_step comes
  // before the next step is issued: a hook that stops training (Python's progress) stops at its step.
  bool on_step_in_time = false;
};

struct TrainResult {
  uint64_t steps = 0;
  double seconds = 0.0;
  uint64_t samples = 0;
  double final_loss = 0.0;         // mean squared sRGB error of the last step
  std::vector<double> loss_curve;  // per step
  bool interrupted = false;
};

class TrainingDiverged : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Trainer {
 public:
  // views: training views with RGBA images; occupancy_mask: permanent mask (may be empty).
  Trainer(NerfModel& model, const std::vector<View>& views, const TrainOptions& options,
          std::vector<uint32_t> occupancy_mask = {});
  ~Trainer();
  TrainResult run();

  // One step with at most one blocking host transfer (without a room model): samples are counted,
  // scanned, fitted and written on the device, the loss is summed there, and the one read per step
  // (the batch's ray and sample counts, which the field's launches need) also brings the previous
  // step's loss. Returns that previous step's batch loss (mean over rays and channels), or nothing
  // when no step is pending (the first step, or after last_loss()). With a room model the step
  // takes the host way (BackgroundField reads the rays back) and its loss is known at once.
  std::optional<double> advance();
  // The loss of the last step, read back now if advance() left it on the device (one blocking read);
  // nothing when it was already returned. Afterwards no step is pending.
  std::optional<double> last_loss();
  // advance() then last_loss(): one step, returning its own batch loss (a second synchronisation).
  // For tests and callers that need each loss at once.
  double step();
  uint64_t steps_done() const { return step_; }
  uint64_t samples_done() const { return samples_; }
  uint64_t rays_done() const { return rays_; }
  // The room model trained beside the subject (nullptr without one).
  const BackgroundField* background() const { return background_.get(); }
  // For callers that drive step() themselves: the training time so far (learning-rate schedule).
  void set_elapsed(double seconds) { elapsed_ = seconds; }
  // The whole state the next step depends on (checkpoint.h), and its restoration before run():
  // run() then continues at the checkpoint's step and takes the steps the stopped training would have.
  TrainingState state() const;
  void restore(const TrainingState& state);

 private:
  double run_fraction(double elapsed) const;  // of the steps or seconds, whichever is further
  float learning_rate(double elapsed) const;
  RayPriors opacity_prior() const;  // the room model's opacity prior now (its weight ramps in)
  // The room model's steps alone before the subject's first (BackgroundOptions::room_first); stops
  // early when interrupted (run() then stops before its first step).
  void train_room_first(Progress& bar);
  // After the last step: the interior's log, the result's figures, the final checkpoint, then the
  // model's occupancy as its density gives it (OccupancyUpdater::without_kept) and the final snapshot.
  void finish_run(TrainResult& result, double seconds, Progress& bar);
  [[noreturn]] void diverged(double loss, uint64_t at_step);
  bool save_snapshot(double elapsed);    // false when nothing was saved (no path, or no step trained)
  void save_checkpoint(double elapsed);  // the state to options_.checkpoint_path (when set)

  NerfModel& model_;
  TrainOptions options_;
  std::unique_ptr<DeviceViews> views_;
  std::unique_ptr<RayBatch> batch_;
  std::unique_ptr<OccupancyUpdater> occupancy_;
  std::unique_ptr<BackgroundField> background_;
  // The opacity prior's zones (RayPriors): the subject's keep cells, then the lean cells (its
  // volume outside its core; BackgroundOptions::subject); zone_res_^3 each, 0: none.
  cl::Buffer<uint32_t> zones_;
  uint32_t zone_res_ = 0;
  uint64_t step_ = 0;
  uint32_t n_rays_;
  uint64_t samples_ = 0, rays_ = 0;
  double elapsed_ = 0.0;
  double resumed_elapsed_ = 0.0;  // training seconds before run() (a restored checkpoint's)
  double last_loss_ = 0.0;        // the last step loss known (kept by checkpoints)
  std::vector<float> good_params_;
  OccupancyGrid good_occupancy_;
  uint64_t good_step_ = 0;
  // The loss of the last step: not pending, summed on the device (rays of that step in
  // pending_rays_), or known on the host (pending_value_).
  enum class PendingLoss { None, OnDevice, Known } pending_ = PendingLoss::None;
  uint32_t pending_rays_ = 0;
  double pending_value_ = 0.0;
};

}  // namespace lorgnette::nerf
