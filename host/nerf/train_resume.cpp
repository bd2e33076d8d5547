// Resuming a training (train_resume.h).
#include "host/nerf/train_resume.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "host/nerf/blob_table.h"

namespace lorgnette::nerf {
namespace {

using nlohmann::json;

json room_json(const BackgroundOptions& r) {
  return {{"enabled", r.enabled},
          {"box_scale", r.box_scale},
          {"levels", r.levels},
          {"log2_table", r.log2_table},
          {"finest_resolution", r.finest_resolution},
          {"occupancy_resolution", r.occupancy_resolution},
          {"steps_per_diagonal", r.steps_per_diagonal},
          {"sh_degree", r.sh_degree},
          {"cutout_margin", r.cutout_margin},
          {"volume_cutout_margin", r.volume_cutout_margin},
          {"lr_scale", r.lr_scale},
          {"batch_scale", r.batch_scale},
          {"spread_over_rays", r.spread_over_rays},
          {"opacity_prior", r.opacity_prior},
          {"opacity_prior_start", r.opacity_prior_start},
          {"opacity_prior_ramp", r.opacity_prior_ramp},
          {"room_clear", r.room_clear},
          {"room_clear_tolerance", r.room_clear_tolerance},
          {"subject_explains", r.subject_explains},
          {"lean_gate", r.lean_gate},
          {"solid_pull", r.solid_pull},
          {"solid_reach_mm", r.solid_reach_mm},
          {"neck_clear", r.neck_clear},
          {"room_first", r.room_first},
          {"keep_pull", r.keep_pull},
          {"keep_far_mm", r.keep_far_mm},
          {"keep_far_neck_mm", r.keep_far_neck_mm},
          {"subject_zones", r.subject.has_value()}};
}

json train_json(const TrainOptions& t) {
  return {
      {"steps", t.steps},
      {"seconds", t.seconds},
      {"seed", t.seed},
      {"loss_kind", t.loss_kind},
      {"lr", t.adam.lr},
      {"beta1", t.adam.beta1},
      {"beta2", t.adam.beta2},
      {"eps", t.adam.eps},
      {"mlp_weight_decay", t.adam.mlp_weight_decay},
      {"sparse_hash", t.adam.sparse_hash},
      {"decay_start", t.decay_start},
      {"final_lr_fraction", t.final_lr_fraction},
      {"occupancy",
       {t.occupancy.update_every, t.occupancy.warmup_steps, t.occupancy.decay, t.occupancy.threshold_alpha}},
      {"room", room_json(t.background)}};
}

}  // namespace

std::string checkpoint_for(const TrainOptions& o) {
  if (!o.checkpoint_path.empty()) return o.checkpoint_path;
  return o.snapshot_path.empty() ? std::string() : checkpoint_path_for(o.snapshot_path);
}

std::string second_checkpoint(const std::string& checkpoint) {
  return checkpoint.empty() ? checkpoint : checkpoint + ".second";
}

void remove_checkpoints(const std::string& checkpoint) {
  if (checkpoint.empty()) return;
  std::error_code ec;
  std::filesystem::remove(checkpoint, ec);
  std::filesystem::remove(second_checkpoint(checkpoint), ec);
}

CheckpointKey checkpoint_key(const dataset::Dataset& ds, const TrainPlan& plan, const TrainJob& job) {
  const ModelSizing& s = plan.sizing;
  const std::vector<uint32_t>& mask = s.occupancy_mask;
  json j = train_json(plan.train);
  j["field"] = s.field.to_json();
  j["aabb"] = {s.aabb.min, s.aabb.max};
  j["occupancy_resolution"] = s.occupancy_resolution;
  j["march_step"] = s.step;
  j["batch_log2"] = plan.batch_log2;
  j["deterministic"] = job.deterministic;
  j["occupancy_mask"] = checksum_hex(
      snapshot_checksum({reinterpret_cast<const char*>(mask.data()), mask.size() * sizeof(uint32_t)}));
  return {dataset_fingerprint(ds), j.dump()};
}

void resume_training(Trainer& trainer, const TrainOptions& o, TrainJob::Resume mode) {
  if (mode == TrainJob::Resume::Off || o.checkpoint_path.empty()) return;
  const std::string of = o.steps ? fmt::format("{}", o.steps) : fmt::format("{:.0f} s", o.seconds);
  try {
    std::optional<TrainingState> s = read_checkpoint(o.checkpoint_path, o.checkpoint_key);
    if (!s) {
      spdlog::info("no training checkpoint at '{}': training from step 0", o.checkpoint_path);
      return;
    }
    trainer.restore(*s);
    spdlog::info("resuming at step {} of {} from the checkpoint '{}'", s->step, of, o.checkpoint_path);
  } catch (const CheckpointCorrupt& e) {
    if (mode == TrainJob::Resume::Required) throw;
    spdlog::warn("{}. Training from step 0 instead", e.what());
  } catch (const CheckpointMismatch& e) {
    if (mode == TrainJob::Resume::Required) throw;
    spdlog::warn("{}. Training from step 0 instead", e.what());
  }
}

}  // namespace lorgnette::nerf
