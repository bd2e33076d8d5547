// TrainSettings -> LoadOptions and TrainJob, with the bounds checks (train_settings.h).
#include "host/nerf/train_settings.h"

#include <fmt/format.h>

#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "host/nerf/checkpoint.h"
#include "host/util/bounds.h"
#include "host/util/output_folder.h"

namespace lorgnette::nerf {
namespace b = bounds;

namespace {

void validate_size(const TrainSettings& s) {
  if (s.aabb) {
    for (int a = 0; a < 3; ++a)
      check_bound(b::kAabbCoord, s.aabb->min[a]), check_bound(b::kAabbCoord, s.aabb->max[a]);
    if (!s.aabb->valid()) throw OutOfRange("--aabb: max must exceed min on every axis");
  }
  check_bound_or_zero(b::kAabbScale, s.aabb_scale);
  check_bound_or_zero(b::kTrainStep, s.step);
  check_bound_or_zero(b::kFinestRes, s.finest_res);
  check_bound_or_zero(b::kLog2Table, s.log2_table);
  check_bound_or_zero(b::kLevels, s.levels);
  check_bound_or_zero(b::kOccRes, s.occ_res);
}

void validate_room(const BackgroundOptions& r) {
  check_bound(b::kOpacityPrior, r.opacity_prior);
  check_bound(b::kRoomClear, r.room_clear);
  check_bound(b::kRoomClearTolerance, r.room_clear_tolerance);
  check_bound(b::kSubjectExplains, r.subject_explains);
  check_bound(b::kLeanGate, r.lean_gate);
  check_bound(b::kSolidPull, r.solid_pull);
  check_bound(b::kSolidReach, r.solid_reach_mm);
  check_bound(b::kNeckClear, r.neck_clear);
  check_bound(b::kPriorStart, r.opacity_prior_start);
  check_bound(b::kRoomFirst, r.room_first);
  check_bound(b::kKeepPull, r.keep_pull);
  check_bound(b::kKeepFar, r.keep_far_mm);
  check_bound(b::kKeepFarNeck, r.keep_far_neck_mm);
}

}  // namespace

void validate(const TrainSettings& s) {
  if (s.steps && s.seconds)
    throw std::invalid_argument("give --steps or --seconds (Python: steps or seconds), not both");
  if (s.steps) check_bound(b::kTrainSteps, double(*s.steps));
  if (s.seconds) check_bound(b::kTrainSeconds, *s.seconds);
  check_bound_or_zero(b::kBatchLog2, s.batch_log2);
  check_bound(b::kDownscale, s.downscale);
  check_bound_or_zero(b::kMaxSide, s.max_side);
  if (s.hair_mm) check_bound(b::kHairMm, *s.hair_mm);
  check_bound(b::kLearningRate, s.lr);
  check_bound(b::kSnapshotEvery, s.snapshot_every);
  if (s.background != "auto" && s.background != "on" && s.background != "off")
    throw std::invalid_argument(
        fmt::format("--background (Python: background) must be auto, on or off, found '{}'", s.background));
  validate_size(s);
  validate_room(s.room);
}

dataset::LoadOptions train_load_options(const TrainSettings& s) {
  validate(s);
  dataset::LoadOptions lo;
  lo.downscale = int(s.downscale);
  lo.max_side = int(s.max_side);
  lo.max_image_bytes = kTrainImageBytes;
  lo.splits = {dataset::Split::Train};
  return lo;
}

TrainJob train_job(const TrainSettings& s) {
  validate(s);
  TrainJob job;
  job.sizing.aabb = s.aabb;
  job.sizing.use_masks = s.masks;
  if (s.finest_res) job.sizing.finest_resolution = s.finest_res;
  if (s.log2_table) job.sizing.log2_table_size = s.log2_table;
  if (s.levels) job.sizing.levels = s.levels;
  if (s.occ_res) job.sizing.occupancy_resolution = s.occ_res;
  if (s.step > 0.0f) job.sizing.step = s.step;
  job.aabb_scale = s.aabb_scale;
  job.batch_log2 = s.batch_log2;
  job.deterministic = s.deterministic;
  job.background = s.background;
  TrainOptions& to = job.train;
  to.steps = s.steps.value_or(0);
  to.seconds = s.seconds.value_or(0.0);
  to.seed = s.seed;
  to.adam.lr = s.lr;
  to.background = s.room;  // train_on_dataset adds whether the room model runs and the subject's zones
  to.loss_kind = s.linear_loss ? LOSS_L2_LINEAR : LOSS_L2_SRGB;
  to.snapshot_path = s.output;
  to.snapshot_every_seconds = s.snapshot_every;
  job.resume = s.resume ? TrainJob::Resume::Required : TrainJob::Resume::Off;
  to.progress = s.progress;
  return job;
}

std::optional<Aabb> parse_aabb(const std::string& text) {
  if (text.empty()) return std::nullopt;
  std::stringstream ss(text);
  Aabb box;
  char comma;
  for (int i = 0; i < 6; ++i) {
    double v;
    if (!(ss >> v)) throw std::invalid_argument("--aabb needs six numbers: minx,miny,minz,maxx,maxy,maxz");
    check_bound(b::kAabbCoord, v);
    (i < 3 ? box.min[i] : box.max[i - 3]) = float(v);
    if (i < 5) ss >> comma;
  }
  if (!box.valid()) throw OutOfRange("--aabb: max must exceed min on every axis");
  return box;
}

void refuse_overwrite(const TrainSettings& s, bool force, const std::string& force_flag,
                      const std::string& resume_flag) {
  namespace fs = std::filesystem;
  const std::string ckpt = checkpoint_path_for(s.output);
  const bool has_ckpt = fs::exists(ckpt);
  if (has_ckpt && !s.resume && !force)
    throw std::runtime_error(fmt::format(
        "'{}' holds an unfinished training of '{}': pass {} to continue it, or {} to train from the start",
        ckpt, s.output, resume_flag, force_flag));
  if (fs::exists(s.output) && !force && !(s.resume && has_ckpt))
    throw std::runtime_error(
        fmt::format("'{}' exists: pass {} to overwrite it or choose another output", s.output, force_flag));
}

void refuse_output_onto_dataset(const std::string& output, const std::string& data) {
  std::vector<std::string> inputs{data};
  std::error_code ec;
  if (std::filesystem::is_directory(data, ec))
    for (const auto& e : std::filesystem::directory_iterator(data, ec))
      if (e.path().extension() == ".json") inputs.push_back(e.path().string());
  refuse_output_onto_input(output, inputs);
}

}  // namespace lorgnette::nerf
