// `lorgnette train DATA -o MODEL`: loads the training split, chooses the subject box (--box: the
// dataset's aabb, the alpha-mask hull, the head box from landmarks, or the cameras; see
// capture/subject_box.h), sizes the model from the data (every value overridable), trains with a
// progress bar and saves the .lnerf snapshot (also on Ctrl-C; a diverging run keeps its last good
// snapshot and exits non-zero).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <sstream>

#include "capture/subject_box.h"
#include "host/dataset/dataset.h"
#include "host/nerf/background_field.h"
#include "host/nerf/train_job.h"
#include "host/util/file_write.h"
#include "host/util/interrupt.h"
#include "tools/lorgnette/command.h"

namespace lorgnette::cli {
namespace {

struct TrainArgs {
  std::string data, output, aabb, box = "auto", background = "auto";
  uint64_t steps = 0;
  double seconds = 0.0;
  uint32_t seed = 1337, batch_log2 = 0, finest = 0, log2_table = 0, levels = 0, occ_res = 0, downscale = 1;
  uint32_t max_side = 0;
  float step = 0.0f, lr = 1e-2f, aabb_scale = 0.0f;
  nerf::BackgroundOptions room;  // the room model's prior and clearing options (defaults shown in --help)
  fit::HeadBoxOptions head;      // the head box's extents (--hair)
  double snapshot_every = 120.0;
  bool deterministic = false, force = false, no_masks = false, linear_loss = false;
};

std::optional<nerf::Aabb> parse_aabb(const std::string& text) {
  if (text.empty()) return std::nullopt;
  std::stringstream ss(text);
  nerf::Aabb box;
  char comma;
  for (int i = 0; i < 6; ++i) {
    float v;
    if (!(ss >> v)) throw std::runtime_error("--aabb needs six numbers: minx,miny,minz,maxx,maxy,maxz");
    (i < 3 ? box.min[i] : box.max[i - 3]) = v;
    if (i < 5) ss >> comma;
  }
  if (!box.valid()) throw std::runtime_error("--aabb: max must exceed min on every axis");
  return box;
}

// The model's folder must take a file now, not after the training: a read-only folder or a full
// disk is an error before the dataset is even loaded.
void check_model_output(const std::string& output) {
  if (std::filesystem::is_directory(output))
    throw std::runtime_error(
        fmt::format("-o '{}' is a folder: give the model file to write, e.g. {}/head.lnerf", output, output));
  check_writable_folder(std::filesystem::path(output).parent_path().string(),
                        fmt::format("the model (-o {})", output));
}

void run_train(const TrainArgs& a, GlobalOptions& global) {
  if (a.seconds < 0.0)
    throw std::runtime_error("--seconds must be positive (or leave it out for the default budget)");
  if (std::filesystem::exists(a.output) && !a.force)
    throw std::runtime_error("'" + a.output + "' exists: pass --force to overwrite it or choose another -o");
  check_model_output(a.output);
  if (a.batch_log2 != 0 && (a.batch_log2 < 10 || a.batch_log2 > 22))
    throw std::runtime_error("--batch-log2 must be within 10..22");
  dataset::LoadOptions lo;
  lo.downscale = int(a.downscale);
  lo.max_side = int(a.max_side);
  lo.max_image_bytes = nerf::kTrainImageBytes;
  lo.splits = {dataset::Split::Train};
  dataset::Dataset ds = dataset::load_dataset(a.data, lo);
  if (interrupted())
    throw std::runtime_error(fmt::format(
        "interrupted while loading the dataset: nothing was trained or saved ('{}' is unchanged)", a.output));
  spdlog::info("dataset: {} ({}), {} frames", a.data, ds.format, ds.frames.size());

  nerf::TrainJob job;
  job.sizing.aabb = parse_aabb(a.aabb);
  job.sizing.use_masks = !a.no_masks;
  if (job.sizing.aabb)
    spdlog::info("subject box: --aabb (given on the command line)");
  else
    capture::apply_subject_box(ds, capture::box_source_from_string(a.box), !a.no_masks, job, a.head);
  if (a.finest) job.sizing.finest_resolution = a.finest;
  if (a.log2_table) job.sizing.log2_table_size = a.log2_table;
  if (a.levels) job.sizing.levels = a.levels;
  if (a.occ_res) job.sizing.occupancy_resolution = a.occ_res;
  if (a.step > 0.0f) job.sizing.step = a.step;
  job.aabb_scale = a.aabb_scale;
  job.batch_log2 = a.batch_log2;
  job.deterministic = a.deterministic;
  job.background = a.background;
  nerf::TrainOptions& to = job.train;
  to.steps = a.steps;
  to.seconds = a.seconds;
  to.seed = a.seed;
  to.adam.lr = a.lr;
  to.background = a.room;  // train_on_dataset adds whether the room model runs and the subject's zones
  to.loss_kind = a.linear_loss ? LOSS_L2_LINEAR : LOSS_L2_SRGB;
  to.snapshot_path = a.output;
  to.snapshot_every_seconds = a.snapshot_every;
  to.progress = !global.quiet;
  cl::Runtime rt(global.runtime());
  nerf::TrainJobResult out = nerf::train_on_dataset(rt, ds, job);
  const nerf::TrainResult& r = out.result;
  if (r.interrupted && r.steps == 0)
    spdlog::warn("interrupted before the first training step: nothing was saved ('{}' is unchanged)",
                 a.output);
  else if (r.interrupted)
    spdlog::warn("interrupted after {} steps: the model so far is saved in '{}'", r.steps, a.output);
  else
    spdlog::info("trained {} steps ({} samples) in {:.1f} s ({}); saved '{}'", r.steps, r.samples, r.seconds,
                 out.budget, a.output);
}

void add_train(CLI::App& app, GlobalOptions& global) {
  auto* cmd = app.add_subcommand("train", "train a NeRF on a dataset (transforms.json or NeRF-synthetic)");
  auto a = std::make_shared<TrainArgs>();
  cmd->add_option("DATA", a->data, "dataset directory or json file")->required();
  cmd->add_option("-o,--output", a->output, "model file to write (.lnerf)")->required();
  auto* steps = cmd->add_option("--steps", a->steps,
                                "training steps (default: from the model's size, the same on every device)");
  cmd->add_option("--seconds", a->seconds, "train for this wall-clock time instead of a step count")
      ->excludes(steps);
  cmd->add_option("--seed", a->seed, "random seed");
  cmd->add_flag("--deterministic", a->deterministic, "bitwise reproducible (same seed, same device)");
  cmd->add_flag("--force", a->force, "overwrite an existing model file");
  cmd->add_option("--batch-log2", a->batch_log2,
                  "log2 of the samples per step (default: 18 on a GPU, 16 otherwise)")
      ->check(CLI::Range(10u, 22u));
  cmd->add_option("--lr", a->lr, "base learning rate (default 1e-2)");
  cmd->add_option("--aabb", a->aabb, "bounding box minx,miny,minz,maxx,maxy,maxz (scene units)");
  cmd->add_option("--box", a->box,
                  "subject box: auto (dataset aabb, else mask hull, else head box from landmarks, else "
                  "cameras), dataset, masks, head or cameras (default auto; --aabb overrides)")
      ->check(CLI::IsMember({"auto", "dataset", "masks", "head", "cameras"}));  // before loading the data
  cmd->add_option(
         "--hair", a->head.extents.hair_mm,
         "head box: millimetres of hair (or a hat) above and behind a large skull, and half of what "
         "exceeds the default 30 at its sides; the subject is cut where it stands out further (about "
         "40 mm more). Raise it for a bun, tall hair or a hat")
      ->check(CLI::Range(0.0, capture::kMaxHairMm))
      ->capture_default_str();
  cmd->add_option("--background", a->background,
                  "room model behind the subject, then keep the subject's connected region: auto (mask-less "
                  "datasets with a subject box), on or off")
      ->check(CLI::IsMember({"auto", "on", "off"}));
  // The room model's options start at BackgroundOptions' defaults, which --help shows.
  cmd->add_option(
         "--opacity-prior", a->room.opacity_prior,
         "with the room model: weight of the prior that pushes each ray's opacity to 0 or 1 (0 = off)")
      ->check(CLI::Range(0.0f, 1.0f))
      ->capture_default_str();
  cmd->add_option("--room-clear", a->room.room_clear,
                  "with the room model: where the room's colour matches the pixel, pull the subject's "
                  "opacity to 0 with this many times the opacity prior's weight (0 = off)")
      ->check(CLI::Range(0.0f, 100.0f))
      ->capture_default_str();
  cmd->add_option("--room-clear-tolerance", a->room.room_clear_tolerance,
                  "RMS sRGB difference between the room's colour and the pixel at which --room-clear stops")
      ->check(CLI::Range(0.001f, 1.0f))
      ->capture_default_str();
  cmd->add_option("--lean-gate", a->room.lean_gate,
                  "with the room model and a head box: in the head volume beyond the bare head, the "
                  "clearing's gate is at least this (1: always clear there; 0 = off)")
      ->check(CLI::Range(0.0f, 1.0f))
      ->capture_default_str();
  cmd->add_option("--aabb-scale", a->aabb_scale,
                  "box size factor for datasets without alpha (default: dataset)");
  // The ranges the field and the occupancy grid accept (FieldConfig::validate, occupancy.h), checked
  // here so the message names the flag.
  cmd->add_option("--finest-res", a->finest, "finest hash-grid resolution (16..1048576)")
      ->check(CLI::Range(16u, 1u << 20));
  cmd->add_option("--log2-table", a->log2_table, "log2 of the hash-table size per level (8..24)")
      ->check(CLI::Range(8u, 24u));
  cmd->add_option("--levels", a->levels, "hash-grid levels (1..32)")->check(CLI::Range(1u, 32u));
  cmd->add_option("--occ-res", a->occ_res, "occupancy grid resolution (8..512)")->check(CLI::Range(8u, 512u));
  cmd->add_option("--step", a->step, "marching step in scene units");
  cmd->add_option("--downscale", a->downscale, "integer image downscale factor");
  cmd->add_option("--max-side", a->max_side,
                  fmt::format("shrink images so the longer side is at most this (images that would hold "
                              "more than {:.1f} GB in memory shrink on their own, with a warning)",
                              nerf::kTrainImageBytes / 1e9));
  cmd->add_flag("--no-masks", a->no_masks, "ignore alpha masks when sizing the box");
  cmd->add_flag("--linear-loss", a->linear_loss, "L2 on linear instead of sRGB colour");
  cmd->add_option("--snapshot-every", a->snapshot_every, "seconds between snapshots (0: only at the end)");
  cmd->callback([a, &global] { run_train(*a, global); });
}

}  // namespace
LGN_REGISTER_COMMAND(20, add_train);
}  // namespace lorgnette::cli
