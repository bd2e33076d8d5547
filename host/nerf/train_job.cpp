// One-call training from a dataset; see train_job.h.
#include "host/nerf/train_job.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <filesystem>

#include "host/dataset/metric_scale.h"
#include "host/nerf/subject_cut.h"
#include "host/nerf/subject_holes.h"
#include "host/nerf/subject_region.h"
#include "host/nerf/train_resume.h"

namespace lorgnette::nerf {

std::vector<View> training_views(const dataset::Dataset& ds) {
  std::vector<View> views;
  for (const dataset::Frame* f : ds.split(dataset::Split::Train))
    views.push_back({f->camera, &f->image, f->ignore.empty() ? nullptr : &f->ignore});
  if (views.empty())
    throw std::runtime_error("'" + ds.root +
                             "' has no training frames: check the dataset's frame list and splits");
  return views;
}

std::string dataset_fingerprint(const dataset::Dataset& ds) {
  uint64_t h = 1469598103934665603ull;  // FNV-1a over each frame's path, position and focal length
  for (const auto& f : ds.frames)
    for (char c : f.image_path + std::to_string(f.camera.c2w[3]) + std::to_string(f.camera.fx))
      h = (h ^ uint8_t(c)) * 1099511628211ull;
  // A frame's ignore regions change which pixels train, so a checkpoint of other regions is another
  // training; frames without any hash as before.
  for (const auto& f : ds.frames)
    for (const auto& poly : f.ignore)
      for (const auto& v : poly)
        for (char c : std::to_string(v.x()) + "," + std::to_string(v.y()))
          h = (h ^ uint8_t(c)) * 1099511628211ull;
  return fmt::format("{:016x}", h);
}

ViewRange training_view_range(const std::vector<View>& views, const Aabb& box,
                              const SceneNormalisation& normalisation) {
  std::vector<Camera> cams;
  for (const View& v : views) {
    Camera c = v.camera;
    for (int k = 0; k < 3; ++k)
      c.c2w[4 * k + 3] = c.c2w[4 * k + 3] * normalisation.scale + normalisation.offset[k];
    cams.push_back(c);
  }
  return view_range_from_cameras(cams, box.center());
}

TrainPlan plan_training(cl::Runtime& rt, const dataset::Dataset& ds, const std::vector<View>& views,
                        TrainJob job) {
  job.sizing.aabb_scale = job.aabb_scale > 0.0f ? job.aabb_scale : ds.aabb_scale;
  if (!job.sizing.aabb && ds.aabb) {  // the subject's box recorded with the dataset (e.g. by capture)
    Aabb box;
    box.min = (*ds.aabb)[0];
    box.max = (*ds.aabb)[1];
    job.sizing.aabb = box;
    spdlog::info("using the dataset's subject box 'aabb' instead of the automatic one");
  }
  if (job.background != "auto" && job.background != "on" && job.background != "off")
    throw std::invalid_argument("background must be auto, on or off, not '" + job.background + "'");
  TrainPlan plan;
  plan.sizing = choose_model_size(views, job.sizing);
  ModelSizing& sizing = plan.sizing;
  const bool from_cameras = sizing.from.find("cameras") != std::string::npos;
  const bool background =
      job.background == "on" || (job.background == "auto" && !ds.has_alpha && !from_cameras);
  if (background && !job.sizing.log2_table_size && sizing.field.log2_table_size > kRoomCaptureMaxLog2Table) {
    sizing.field.log2_table_size = kRoomCaptureMaxLog2Table;
    sizing.field.validate();
    spdlog::info(
        "hash table capped at 2^{} for a capture with a room model (train_budget.h; --log2-table overrides)",
        kRoomCaptureMaxLog2Table);
  }
  spdlog::info("{}", sizing.summary());
  if (background && job.subject && !job.subject->volume.empty()) {
    std::vector<uint32_t> mask =
        volume_occupancy_mask(job.subject->volume, sizing.aabb, sizing.occupancy_resolution);
    if (!sizing.occupancy_mask.empty())
      for (size_t w = 0; w < mask.size(); ++w) mask[w] &= sizing.occupancy_mask[w];
    const uint64_t cells =
        uint64_t(sizing.occupancy_resolution) * sizing.occupancy_resolution * sizing.occupancy_resolution;
    const uint64_t allowed = mask_count(mask);
    spdlog::info("subject volume: {} of the box's {} occupancy cells ({:.0f} %) may hold the subject: {}",
                 allowed, cells, 100.0 * double(allowed) / double(cells), job.subject->volume.what);
    sizing.occupancy_mask = std::move(mask);
    job.train.background.subject = job.subject;
  }
  plan.batch_log2 = job.batch_log2;
  if (plan.batch_log2 == 0) {
    plan.batch_log2 = device_batch_log2(rt.device());
    spdlog::info("batch: 2^{} samples per step (the default for a {})", plan.batch_log2,
                 rt.device().type_name());
  }
  const bool defaulted = job.train.steps == 0 && !(job.train.seconds > 0.0);
  StepBudget budget;
  if (defaulted) {
    budget = background ? default_training_steps(sizing.field.param_count(), plan.batch_log2,
                                                 kRoomCaptureSamplesPerParameter, kRoomCaptureMinSteps)
                        : default_training_steps(sizing.field.param_count(), plan.batch_log2);
    if (background) budget.why += " (a capture with a room model: train_budget.h)";
    job.train.steps = budget.steps;
  }
  plan.budget = describe_budget(job.train.steps, job.train.seconds, defaulted, budget.why);
  job.train.background.enabled = background;
  plan.background = background;
  plan.train = job.train;
  return plan;
}

std::optional<MetricScale> model_metric_scale(const dataset::Dataset& ds, const SceneNormalisation& n) {
  std::optional<dataset::MetricScale> s = dataset::read_scale_json(ds.root);
  if (!s) return std::nullopt;
  spdlog::info("metric scale from {}: {:.3f} +- {:.3f} mm per dataset unit ({} frames)", s->source,
               s->mm_per_unit, s->uncertainty, s->frames);
  return MetricScale{s->source, s->mm_per_unit / n.scale, s->uncertainty / n.scale};
}

NerfModel planned_model(cl::Runtime& rt, const dataset::Dataset& ds, const std::vector<View>& views,
                        const TrainPlan& plan, const TrainJob& job) {
  const ModelSizing& sizing = plan.sizing;
  NerfModel model(rt, sizing.field, sizing.aabb, sizing.occupancy_resolution, sizing.step,
                  1u << plan.batch_log2, plan.train.seed, job.deterministic);
  model.metadata.dataset_path = std::filesystem::absolute(ds.root).string();
  model.metadata.dataset_hash = dataset_fingerprint(ds);
  model.metadata.device = rt.device().name;
  model.metadata.subject_problem = job.subject_problem;
  model.metadata.metric_scale = model_metric_scale(ds, model.normalisation);
  model.view_range = training_view_range(views, sizing.aabb, model.normalisation);
  spdlog::info("captured directions: {}", model.view_range->summary());
  if (std::string advice = coverage_advice(*model.view_range); !advice.empty()) spdlog::warn("{}", advice);
  return model;
}

namespace {

// One training of `plan` with its room-model aftermath (the subject's connected region, the volume's
// cut check, the hole check); the model is saved to the plan's snapshot path when it changed.
TrainJobResult train_planned(cl::Runtime& rt, const dataset::Dataset& ds, const std::vector<View>& views,
                             TrainPlan plan, const TrainJob& job) {
  NerfModel model = planned_model(rt, ds, views, plan, job);
  spdlog::info("training budget: {}", plan.budget);
  const bool background = plan.background;
  spdlog::info("background: {}",
               background ? "a room model behind the subject (mask-less capture, subject box)"
                          : (ds.has_alpha ? "none (the images' alpha masks separate the subject)" : "none"));
  std::string region;
  plan.train.checkpoint_key = checkpoint_key(ds, plan, job);
  Trainer trainer(model, views, plan.train, plan.sizing.occupancy_mask);
  resume_training(trainer, plan.train, job.resume);
  TrainResult result = trainer.run();
  // As the trainer's own snapshots: an untrained model is never saved.
  const std::string snapshot = result.steps > 0 ? plan.train.snapshot_path : std::string();
  if (background) {
    OccupancyGrid grid = model.occupancy();
    SubjectRegionReport rep = keep_central_region(grid);
    region = rep.summary();
    if (rep.found) model.set_occupancy(std::move(grid));
    spdlog::info("{}", region);
    std::vector<Camera> cameras;
    for (const View& v : views) cameras.push_back(v.camera);
    if (rep.found && job.subject && !job.subject->rim.empty()) {
      const SubjectCutReport cut = check_subject_cut(model, cameras, job.subject->rim);
      spdlog::info("{}", cut.summary());
      if (cut.cut()) spdlog::warn("{}", cut.advice());
    }
    if (rep.found && job.subject && !job.subject->whole.empty()) {
      const HoleReport holes = check_subject_holes(model, cameras, job.subject->whole);
      spdlog::info("{}", holes.summary());
      if (holes.checked)
        model.metadata.holes = holes.holes, model.metadata.holes_worst_view = holes.worst_view;
    }
    if (!rep.found) {
      model.metadata.subject_problem =
          "the subject could not be separated from the room: nothing was reconstructed in the middle of "
          "the subject box. Film the face filling a third of the frame, in focus, sweeping slowly from "
          "one side to the other";
      spdlog::warn("{}", model.metadata.subject_problem);
    }
    if (!snapshot.empty()) model.save(snapshot);
  }
  return {std::move(model),  std::move(plan.sizing),
          std::move(result), std::move(plan.budget),
          background,        region};
}

bool has_holes(const NerfModel& m) { return m.metadata.holes >= kSubjectHoleShare; }

}  // namespace

TrainJobResult train_on_dataset(cl::Runtime& rt, const dataset::Dataset& ds, TrainJob job) {
  std::vector<View> views = training_views(ds);
  TrainPlan plan = plan_training(rt, ds, views, job);
  if (job.on_planned) job.on_planned(plan.train.steps);
  plan.train.checkpoint_path = checkpoint_for(plan.train);
  TrainJobResult out = train_planned(rt, ds, views, plan, job);
  const BackgroundOptions& room = plan.train.background;
  const bool clearing = room.room_clear > 0.0f || room.lean_gate > 0.0f;
  if (has_holes(out.model) && job.retrain_on_holes && clearing && !out.result.interrupted) {
    // The room-explained clearing is the separation that takes skin whose colour the room model also
    // explains (a pale face before a pale wall, #41); without it only the binary prior separates.
    spdlog::warn(
        "the head has holes ({:.2f} % of its worst region transparent): training again without the "
        "room-explained clearing (--room-clear 0 --lean-gate 0), which keeps more of the subject",
        100.0 * out.model.metadata.holes);
    TrainPlan safer = plan;
    safer.train.background.room_clear = 0.0f;
    safer.train.background.lean_gate = 0.0f;
    // The second training snapshots beside the first model, which stays in place until the second
    // is chosen: an interrupt or a kill during it never leaves a less trained model at the output.
    const std::string first_path = plan.train.snapshot_path;
    if (!first_path.empty()) safer.train.snapshot_path = first_path + ".second";
    safer.train.checkpoint_path = second_checkpoint(plan.train.checkpoint_path);
    TrainJobResult again = train_planned(rt, ds, views, safer, job);
    // Without the clearing the room is rebuilt as haze in the subject's volume (the synthetic pale
    // selfie: leak 46 -> 98 % of the subject's area for holes 3.2 -> 1.7 %), so the second model is
    // kept only when it is whole and complete; else the first, with the problem recorded below.
    const bool keep_second = !again.result.interrupted && again.model.metadata.holes < kSubjectHoleShare;
    if (keep_second) {
      again.result.seconds += out.result.seconds;
      out = std::move(again);
      if (!first_path.empty()) out.model.save(first_path);
    } else if (again.result.interrupted) {
      out.result.interrupted = true;  // the command still reports the interrupt
    }
    if (!first_path.empty()) std::filesystem::remove(safer.train.snapshot_path);
  }
  if (has_holes(out.model) && out.model.metadata.subject_problem.empty()) {
    HoleReport rep;
    rep.checked = true;
    rep.holes = out.model.metadata.holes;
    rep.worst_view = out.model.metadata.holes_worst_view;
    out.model.metadata.subject_problem = rep.advice();
    spdlog::warn("{}", out.model.metadata.subject_problem);
    if (!plan.train.snapshot_path.empty()) out.model.save(plan.train.snapshot_path);
  }
  // The model is complete: its checkpoints are of no more use (kept after an interrupt, to resume).
  if (!out.result.interrupted && !job.keep_checkpoint) remove_checkpoints(plan.train.checkpoint_path);
  return out;
}

}  // namespace lorgnette::nerf
