// Trainer: the step (sample, forward, loss, backward, Adam, occupancy) and the loop around it
// (schedule, progress, snapshots, Ctrl-C, divergence).
#include "host/nerf/trainer.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>

#include "host/util/interrupt.h"
#include "host/util/progress.h"
#include "kernels/train/occupancy.h"

namespace lorgnette::nerf {
namespace {

// The cells of `solid` over `box` at res^3 whose centre lies in it (not the occupancy mask's
// outward rule: a cell the pull acts on must lie inside the subject).
std::vector<uint32_t> solid_cells(const SubjectVolume& solid, const Aabb& box, uint32_t res) {
  std::vector<uint32_t> bits(occ_word_count(res), 0u);
  for (uint32_t z = 0; z < res; ++z)
    for (uint32_t y = 0; y < res; ++y)
      for (uint32_t x = 0; x < res; ++x) {
        const uint32_t idx[3] = {x, y, z};
        Vec3f p;
        for (int a = 0; a < 3; ++a) p[a] = box.min[a] + (float(idx[a]) + 0.5f) / float(res) * box.extent(a);
        const uint32_t cell = x + res * (y + res * z);
        if (solid.contains(p)) bits[cell >> 5] |= 1u << (cell & 31u);
      }
  return bits;
}

// The subject's certain interior (its reach's base: SubjectZones::reach, else the interior) grown by `mm`
// towards its skin, where the prior's zones judge whether a ray crosses it (render.h, the "reach"
// field); the base itself without a scale or a growth.
SubjectVolume solid_reach(const SubjectZones& z, float mm) {
  SubjectVolume v = z.reach.empty() ? z.solid : z.reach;
  if (!(mm > 0.0f) || !(z.mm_per_unit > 0.0f)) return v;
  for (OrientedShape& part : v.parts) part = part.grown(mm / z.mm_per_unit);
  return v;
}

// What the neck's keep cells clear (BackgroundOptions::neck_clear) with the skin's colours sampled.
void log_neck_rule(float tolerance, const SkinChroma& skin) {
  if (skin.chroma.empty()) {
    spdlog::info("no skin colours could be sampled on the face: the neck's cells keep the binary prior");
    return;
  }
  std::vector<std::string> list;
  for (const auto& c : skin.chroma) list.push_back(fmt::format("{:.3f},{:.3f}", c[0], c[1]));
  spdlog::info(
      "the neck's cells clear rays whose pixel's chromaticity lies over {:.3f} (+ the skin's spread {:.3f}) "
      "from the skin's {} (r, g: {}, each with up to {:.0f} % of neutral sheen), unless darker than "
      "luminance {:.4f}",
      tolerance, skin.spread, skin.chroma.size(), fmt::join(list, " "), 100.0f * SKIN_SHEEN_MAX,
      skin.lum_floor);
}

// How the far-wall rule bounds the body below the box (BackgroundOptions::keep_far_neck_mm), for the
// log line that states the rule.
std::string keep_far_column(const BackgroundOptions& b) {
  const NeckColumn c = neck_column(b);
  const std::string seen =
      c.patches ? fmt::format("{} of {} patches beside the neck may be skin", c.skin_like, c.patches)
                : std::string("no patch beside the neck was seen");
  if (c.applies)
    return fmt::format("; {}, so below the box only the room within {:.0f} mm of the neck's axis is the body",
                       seen, b.keep_far_neck_mm);
  return b.keep_far_neck_mm > 0.0f && b.subject->base ? fmt::format("; {}: the body's box is whole", seen)
                                                      : std::string();
}

// The opacity prior's zones (RayPriors): the subject's keep cells, then the lean cells (outside its
// core, not kept, and allowed by the subject's permanent occupancy mask when it has one, which holds
// its volume); empty when neither applies.
std::vector<uint32_t> prior_zones(const BackgroundOptions& b, const NerfModel& model,
                                  const std::vector<uint32_t>& allowed) {
  const bool keep = keep_cells_apply(b);
  const bool lean = b.room_clear > 0.0f && b.lean_gate > 0.0f && b.subject && !b.subject->core.empty();
  const bool solid = b.solid_pull > 0.0f && b.subject && !b.subject->solid.empty();
  if (!keep && !lean && !solid) return {};
  const uint32_t res = model.occupancy_resolution(), words = occ_word_count(res);
  std::vector<uint32_t> zones(4 * size_t(words), 0u);
  if (solid) {
    const std::vector<uint32_t> s = solid_cells(b.subject->solid, model.aabb(), res);
    std::copy(s.begin(), s.end(), zones.begin() + 2 * words);
    const std::vector<uint32_t> r = solid_cells(solid_reach(*b.subject, b.solid_reach_mm), model.aabb(), res);
    for (uint32_t w = 0; w < words; ++w) zones[3 * words + w] = r[w] | s[w];
  }
  if (keep) {
    const std::vector<uint32_t> k = volume_occupancy_mask(b.subject->keep, model.aabb(), res);
    std::copy(k.begin(), k.end(), zones.begin());
  }
  if (lean) {
    const std::vector<uint32_t> core = volume_occupancy_mask(b.subject->core, model.aabb(), res);
    for (uint32_t w = 0; w < words; ++w)
      zones[words + w] = ~core[w] & ~zones[w] & (allowed.empty() ? ~0u : allowed[w]);
  }
  spdlog::info(
      "clearing zones: {} cells keep the binary prior (the neck), {} lean towards the room "
      "(gate >= {:.2f}: the volume beyond the bare head), {} are the subject's certain interior",
      mask_count({zones.begin(), zones.begin() + words}),
      mask_count({zones.begin() + words, zones.begin() + 2 * words}), b.lean_gate,
      mask_count({zones.begin() + 2 * words, zones.begin() + 3 * words}));
  if (keep && b.neck_clear > 0.0f) log_neck_rule(b.neck_clear, b.subject->skin);
  if (keep_far_applies(b))
    spdlog::info(
        "the neck's cells clear rays as far as the room's colour behind them comes from over {:.0f} mm "
        "beyond the subject's box (a wall, not the body){}",
        b.keep_far_mm, keep_far_column(b));
  if (solid && b.solid_reach_mm > 0.0f && b.subject->mm_per_unit > 0.0f)
    spdlog::info("rays within {:.0f} mm of the certain interior are the subject's ({} cells, kept occupied)",
                 b.solid_reach_mm, mask_count({zones.begin() + 3 * words, zones.end()}));
  return zones;
}

// The cells that stay occupied whatever their density (OccupancyUpdater::set_interior): with the pull
// on, the interior's reach (prior_zones' fourth field, which holds the interior), since a ray counts as
// crossing it by its samples there, and a reach whose cells the density left would let the clearing
// take the hair and skin between the interior and the surface. Empty with the pull off.
std::vector<uint32_t> kept_reach(const std::vector<uint32_t>& zones, float solid_pull) {
  if (!(solid_pull > 0.0f) || zones.empty()) return {};
  const size_t words = zones.size() / 4;
  return {zones.begin() + 3 * std::ptrdiff_t(words), zones.end()};
}

// How much of the subject's certain interior the density alone left unoccupied: where that is more than
// a few cells, the separation emptied the inside of the head (the room took it).
void log_interior(const OccupancyUpdater& occ, float solid_pull) {
  if (!occ.interior_cells()) return;
  spdlog::info(
      "the subject's certain interior: the density left {} of its {} cells ({:.1f} %) unoccupied at the last "
      "occupancy update ({})",
      occ.interior_empty(), occ.interior_cells(),
      100.0 * double(occ.interior_empty()) / double(occ.interior_cells()),
      solid_pull > 0.0f ? "kept occupied: rays through them are the subject's" : "emptied: --solid-pull 0");
}

}  // namespace

Trainer::Trainer(NerfModel& model, const std::vector<View>& views, const TrainOptions& options,
                 std::vector<uint32_t> occupancy_mask)
    : model_(model), options_(options) {
  if (options.steps == 0 && !(options.seconds > 0.0))
    throw std::invalid_argument("training needs a limit: give --steps N or --seconds S");
  cl::Runtime& rt = model.runtime();
  views_ = std::make_unique<DeviceViews>(rt, views, true);
  if (views_->ignored_pixels() > 0)
    spdlog::info(
        "training leaves out {} of its {} pixels ({:.2f} %: the views' ignore regions, e.g. a held card)",
        views_->ignored_pixels(), views_->total_pixels(),
        100.0 * double(views_->ignored_pixels()) / double(views_->total_pixels()));
  uint32_t batch = model.field().max_batch();
  batch_ = std::make_unique<RayBatch>(model, batch);
  if (!occupancy_mask.empty()) {
    OccupancyGrid grid = model.occupancy();
    if (occupancy_mask.size() != grid.bits.size())
      throw std::invalid_argument("occupancy mask size does not match the model's occupancy grid");
    for (size_t w = 0; w < grid.bits.size(); ++w) grid.bits[w] &= occupancy_mask[w];
    model.set_occupancy(std::move(grid));
  }
  const std::vector<uint32_t> zones = options.background.enabled
                                          ? prior_zones(options.background, model, occupancy_mask)
                                          : std::vector<uint32_t>{};
  occupancy_ =
      std::make_unique<OccupancyUpdater>(model, options.occupancy, options.seed, std::move(occupancy_mask));
  const BackgroundOptions& b = options.background;
  if (b.enabled && b.subject && !b.subject->solid.empty())
    occupancy_->set_interior(solid_cells(b.subject->solid, model.aabb(), model.occupancy_resolution()),
                             kept_reach(zones, b.solid_pull));
  n_rays_ = std::max<uint32_t>(64, batch / 32);
  if (options.background.enabled) {
    background_ =
        std::make_unique<BackgroundField>(rt, model, *views_, options.background, batch, options.seed);
    spdlog::info("{}", background_->summary());
    if (!zones.empty()) {
      zone_res_ = model.occupancy_resolution();
      zones_ = cl::Buffer<uint32_t>(rt, zones);
    }
  }
}

Trainer::~Trainer() = default;

double Trainer::run_fraction(double elapsed) const {
  double f = 0.0;
  if (options_.steps) f = double(step_) / double(options_.steps);
  if (options_.seconds > 0.0) f = std::max(f, elapsed / options_.seconds);
  return f;
}

RayPriors Trainer::opacity_prior() const {
  const BackgroundOptions& b = options_.background;
  if (!background_ || !(b.opacity_prior > 0.0f)) return {};
  RayPriors p;
  p.weight = b.opacity_prior * opacity_prior_share(b, step_);
  p.room_clear = b.room_clear;
  p.room_clear_tolerance = b.room_clear_tolerance;
  p.subject_explains = b.subject_explains;
  if (zone_res_)
    p.zones = &zones_, p.zone_res = zone_res_, p.lean_gate = b.lean_gate, p.solid_pull = b.solid_pull,
    p.keep_pull = b.keep_pull;
  if (zone_res_ && b.neck_clear > 0.0f && b.subject && !b.subject->skin.chroma.empty())
    p.skin = &b.subject->skin, p.skin_tolerance = skin_tolerance(b);
  return p;
}

float Trainer::learning_rate(double elapsed) const {
  const double f = run_fraction(elapsed);
  double t = std::clamp((f - options_.decay_start) / std::max(1e-9, 1.0 - options_.decay_start), 0.0, 1.0);
  return float(options_.adam.lr * std::pow(options_.final_lr_fraction, t));
}

std::optional<double> Trainer::advance() {
  field::Field& field = model_.field();
  const uint32_t batch = field.max_batch();
  SampleParams p = sample_params_for(model_, *views_);
  p.mode = SAMPLE_MODE_TRAIN;
  p.n_rays = n_rays_;
  p.seed = options_.seed;
  p.iteration = static_cast<uint32_t>(step_);
  std::optional<double> previous;
  uint64_t counted = 0;
  uint32_t end = 0, n = 0;
  if (background_) {  // the host way: the room model needs the subject's counts on the host
    previous = last_loss();
    const std::vector<uint32_t>& counts = batch_->count(p, *views_);
    for (uint32_t c : counts) counted += c;
    end = std::min(batch_->fit(0, batch), background_->count(p, *views_));
    n = batch_->write(p, *views_, 0, end);
    background_->render_backgrounds(p, *views_, end, *batch_);
  } else {
    const RayBatch::DeviceBatch b = batch_->sample_on_device(p, *views_);
    if (pending_ == PendingLoss::OnDevice)
      previous = pending_rays_ ? double(b.previous_loss_sum) / (3.0 * pending_rays_) : 0.0;
    else if (pending_ == PendingLoss::Known)
      previous = pending_value_;
    end = b.rays;
    n = b.samples;
    counted = b.counted;
  }
  // Next step's ray count aims at a full batch (integer arithmetic: deterministic).
  uint64_t want = counted ? uint64_t(batch) * n_rays_ / counted : uint64_t(n_rays_) * 2;
  n_rays_ = static_cast<uint32_t>(std::clamp<uint64_t>(want, 64, batch_->max_rays()));
  if (n > 0)
    field.forward(batch_->positions(), batch_->directions(), n, batch_->sigma(), batch_->rgb(), true);
  if (background_) {
    const double loss_sum = batch_->render(options_.loss_kind, false, 1e-4f, opacity_prior());
    pending_value_ = end ? loss_sum / (3.0 * end) : 0.0;
    pending_ = PendingLoss::Known;
  } else {
    batch_->render_on_device(options_.loss_kind, 1e-4f, opacity_prior());
    pending_rays_ = end;
    pending_ = PendingLoss::OnDevice;
  }
  field::AdamConfig adam = options_.adam;
  adam.lr = learning_rate(elapsed_);
  if (n > 0) {
    field.backward(batch_->dsigma(), batch_->drgb(), n);
    field.adam_step(adam);
  }
  if (background_) background_->backward(*batch_, options_.loss_kind, adam, static_cast<uint32_t>(step_ + 1));
  ++step_;
  samples_ += n;
  rays_ += end;
  occupancy_->maybe_update(static_cast<uint32_t>(step_));
  return previous;
}

std::optional<double> Trainer::last_loss() {
  std::optional<double> loss;
  if (pending_ == PendingLoss::OnDevice)
    loss = pending_rays_ ? double(batch_->loss_sum()) / (3.0 * pending_rays_) : 0.0;
  else if (pending_ == PendingLoss::Known)
    loss = pending_value_;
  pending_ = PendingLoss::None;
  return loss;
}

double Trainer::step() {
  advance();
  return last_loss().value_or(0.0);
}

bool Trainer::save_snapshot(double elapsed) {
  if (options_.snapshot_path.empty()) return false;
  // An untrained model is never saved: it would replace a trained one (train --force stopped in its
  // first second) or pass for a model at -o (stopped while the dataset loaded).
  if (step_ == 0) return false;
  model_.metadata.steps = step_;
  model_.metadata.train_seconds = elapsed;
  model_.metadata.samples_trained = samples_;
  model_.metadata.seed = options_.seed;
  OccupancyGrid training = model_.occupancy();
  model_.set_occupancy(occupancy_->without_kept(training));
  model_.save(options_.snapshot_path);
  model_.set_occupancy(std::move(training));
  return true;
}

void Trainer::diverged(double loss, uint64_t at_step) {
  std::string where =
      options_.snapshot_path.empty() ? "not saved (no snapshot path)" : "not saved (no step to keep)";
  if (!good_params_.empty()) {
    model_.field().upload_params(good_params_);
    model_.set_occupancy(good_occupancy_);
    uint64_t bad_step = step_;
    step_ = good_step_;
    if (save_snapshot(elapsed_)) where = "saved to '" + options_.snapshot_path + "'";
    step_ = bad_step;
  }
  // Resuming would take the same steps to the same divergence: the checkpoint is of no use.
  std::error_code ignored;  // the divergence is the error to report
  if (!options_.checkpoint_path.empty()) std::filesystem::remove(options_.checkpoint_path, ignored);
  throw TrainingDiverged(fmt::format(
      "training diverged: the loss became {} at step {}; kept the last good parameters (step {}), {}. "
      "Lower the learning rate (--lr, now {}) and train again",
      loss, at_step, good_step_, where, options_.adam.lr));
}

void Trainer::train_room_first(Progress& bar) {
  const uint32_t n = options_.background.room_first;
  if (!background_ || n == 0 || step_ > 0) return;
  SampleParams p = sample_params_for(model_, *views_);
  p.mode = SAMPLE_MODE_TRAIN;
  p.n_rays = n_rays_;
  p.seed = options_.seed ^ 0x5bd1e995u;  // other rays than the subject's steps draw
  field::AdamConfig adam = options_.adam;
  adam.lr = learning_rate(0.0);
  for (uint32_t k = 0; k < n && !interrupted(); ++k) {
    p.iteration = k;
    const std::vector<uint32_t> counts = batch_->count(p, *views_);
    const uint32_t end = std::min(batch_->fit(0, model_.field().max_batch()), background_->count(p, *views_));
    batch_->write(p, *views_, 0, end);
    background_->render_backgrounds(p, *views_, end, *batch_);
    background_->train_alone(*batch_, counts, options_.loss_kind, adam, k + 1);
    if (options_.progress) bar.update(0.0, fmt::format("the room model first: step {} of {}", k + 1, n));
  }
  spdlog::info("{}", background_->alone_summary());
}

TrainResult Trainer::run() {
  using clock = std::chrono::steady_clock;
  auto start = clock::now();
  auto last_snapshot = start;
  bool by_steps = options_.steps > 0;
  Progress bar("train", by_steps ? double(options_.steps) : options_.seconds, by_steps ? "steps" : "s");
  TrainResult result;
  double mse_ema = -1.0;
  uint64_t samples_at_start = samples_;
  // The parameters before step `candidate_step` become the good copy once that step's loss is known
  // to be finite (one step later: advance() returns the previous step's loss).
  std::vector<float> candidate;
  OccupancyGrid candidate_occ;
  uint64_t candidate_step = 0;
  // The loss of step `done - 1` (done steps finished): divergence check, curve, callback, progress.
  auto take_loss = [&](double loss, uint64_t done) {
    if (!std::isfinite(loss)) diverged(loss, done);
    if (!candidate.empty() && candidate_step + 1 == done) {
      good_params_ = std::move(candidate);
      good_occupancy_ = std::move(candidate_occ);
      good_step_ = candidate_step;
      candidate.clear();
    }
    result.loss_curve.push_back(loss);
    last_loss_ = loss;
    mse_ema = mse_ema < 0.0 ? loss : 0.95 * mse_ema + 0.05 * loss;
    double now = std::chrono::duration<double>(clock::now() - start).count();
    if (options_.on_step) options_.on_step(done, now, loss);
    if (options_.progress)
      bar.update(by_steps ? double(done) : now,
                 fmt::format("step {}  {:.0f}k samples/s  loss {:.5f}  PSNR {:.2f} dB  {:.1f}% occupied",
                             done, double(samples_ - samples_at_start) / std::max(now, 1e-9) / 1e3, loss,
                             -10.0 * std::log10(std::max(mse_ema, 1e-12)),
                             100.0 * model_.occupancy().occupied_fraction()));
  };
  train_room_first(bar);
  while (true) {
    elapsed_ = resumed_elapsed_ + std::chrono::duration<double>(clock::now() - start).count();
    if (by_steps && step_ >= options_.steps) break;
    if (options_.seconds > 0.0 && elapsed_ >= options_.seconds) break;
    if (interrupted()) {
      result.interrupted = true;
      break;
    }
    std::vector<float> fresh;  // parameters before this step (a candidate once advance() is done)
    OccupancyGrid fresh_occ;
    const uint64_t fresh_step = step_;
    if (step_ % options_.good_copy_every == 0) {
      fresh = model_.field().download_params();
      fresh_occ = model_.occupancy();
    }
    if (std::optional<double> previous = advance()) take_loss(*previous, step_ - 1);
    if (!fresh.empty()) {
      candidate = std::move(fresh);
      candidate_occ = std::move(fresh_occ);
      candidate_step = fresh_step;
    }
    if (options_.on_step_in_time)
      if (std::optional<double> loss = last_loss()) take_loss(*loss, step_);
    if (options_.snapshot_every_seconds > 0.0 &&
        std::chrono::duration<double>(clock::now() - last_snapshot).count() >
            options_.snapshot_every_seconds) {
      const double elapsed = resumed_elapsed_ + std::chrono::duration<double>(clock::now() - start).count();
      save_snapshot(elapsed);
      save_checkpoint(elapsed);
      last_snapshot = clock::now();
    }
  }
  if (std::optional<double> loss = last_loss()) take_loss(*loss, step_);
  finish_run(result, std::chrono::duration<double>(clock::now() - start).count(), bar);
  return result;
}

void Trainer::finish_run(TrainResult& result, double seconds, Progress& bar) {
  log_interior(*occupancy_, options_.background.solid_pull);
  result.seconds = seconds;
  if (options_.progress) bar.finish(fmt::format("{} steps in {:.1f} s", step_, result.seconds));
  result.steps = step_;
  result.samples = samples_;
  result.final_loss = result.loss_curve.empty() ? last_loss_ : result.loss_curve.back();
  model_.metadata.final_loss = float(result.final_loss);
  save_checkpoint(resumed_elapsed_ + result.seconds);  // the training's state, its kept cells included
  model_.set_occupancy(occupancy_->without_kept(model_.occupancy()));
  if (!save_snapshot(resumed_elapsed_ + result.seconds) && !options_.snapshot_path.empty())
    spdlog::warn("no training step finished: nothing was saved to '{}'", options_.snapshot_path);
}

}  // namespace lorgnette::nerf
