// `lorgnette train DATA -o MODEL`: the flags become nerf::TrainSettings (checked against
// host/util/bounds.h, as Python's train() is); capture::prepare_training loads the training split and
// chooses the subject box (--box: the dataset's aabb, the alpha-mask hull, the head box from
// landmarks, or the cameras; see capture/subject_box.h); the model is sized from the data (every
// value overridable), trained with a progress bar and saved as a .lnerf snapshot (also on Ctrl-C; a
// diverging run keeps its last good snapshot and exits non-zero).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <filesystem>

#include "capture/subject_box.h"
#include "capture/train_request.h"
#include "host/nerf/checkpoint.h"
#include "host/nerf/train_job.h"
#include "host/nerf/train_settings.h"
#include "host/util/file_write.h"
#include "host/util/interrupt.h"
#include "tools/lorgnette/command.h"

namespace lorgnette::cli {
namespace {

struct TrainArgs {
  std::string data, aabb;
  nerf::TrainSettings settings;  // the flags land here; nerf::validate checks them (host/util/bounds.h)
  uint64_t steps = 0;
  double seconds = 0.0, hair_mm = 0.0;
  bool force = false, no_masks = false;
  CLI::Option *steps_given = nullptr, *seconds_given = nullptr, *hair_given = nullptr;
};

// The model's folder must take a file now, not after the training: a read-only folder or a full
// disk is an error before the dataset is even loaded.
void check_model_output(const std::string& output) {
  if (std::filesystem::is_directory(output))
    throw std::runtime_error(
        fmt::format("-o '{}' is a folder: give the model file to write, e.g. {}/head.lnerf", output, output));
  check_writable_folder(std::filesystem::path(output).parent_path().string(),
                        fmt::format("the model (-o {})", output));
}

void run_train(TrainArgs& a, GlobalOptions& global) {
  nerf::TrainSettings& s = a.settings;
  if (a.steps_given->count()) s.steps = a.steps;
  if (a.seconds_given->count()) s.seconds = a.seconds;
  if (a.hair_given->count()) s.hair_mm = a.hair_mm;
  s.aabb = nerf::parse_aabb(a.aabb);
  s.masks = !a.no_masks;
  s.progress = !global.quiet;
  nerf::validate(s);
  nerf::refuse_output_onto_dataset(s.output, a.data);
  nerf::refuse_overwrite(s, a.force, "--force", "--resume");
  check_model_output(s.output);
  capture::TrainRequest req = capture::prepare_training(a.data, s);
  if (interrupted())
    throw std::runtime_error(fmt::format(
        "interrupted while loading the dataset: nothing was trained or saved ('{}' is unchanged)", s.output));
  cl::Runtime rt(global.runtime());
  nerf::TrainJobResult out = nerf::train_on_dataset(rt, req.dataset, req.job);
  const nerf::TrainResult& r = out.result;
  if (r.interrupted && r.steps == 0)
    spdlog::warn("interrupted before the first training step: nothing was saved ('{}' is unchanged)",
                 s.output);
  else if (r.interrupted)
    spdlog::warn(
        "interrupted after {} steps: the model so far is saved in '{}'; the same command with --resume "
        "continues the training (from '{}')",
        r.steps, s.output, nerf::checkpoint_path_for(s.output));
  else
    spdlog::info("trained {} steps ({} samples) in {:.1f} s ({}); saved '{}'", r.steps, r.samples, r.seconds,
                 out.budget, s.output);
}

// The room model's options, starting at BackgroundOptions' defaults, which --help shows.
void add_room_options(CLI::App* cmd, nerf::BackgroundOptions& room) {
  cmd->add_option(
         "--opacity-prior", room.opacity_prior,
         "with the room model: weight of the prior that pushes each ray's opacity to 0 or 1 (0 = off)")
      ->capture_default_str();
  cmd->add_option("--prior-start", room.opacity_prior_start,
                  "with the room model: the step from which the opacity prior and the room-explained "
                  "clearing ramp in (over 256 steps)")
      ->capture_default_str();
  cmd->add_option("--room-clear", room.room_clear,
                  "with the room model: where the room's colour matches the pixel, pull the subject's "
                  "opacity to 0 with this many times the opacity prior's weight (0 = off)")
      ->capture_default_str();
  cmd->add_option("--room-clear-tolerance", room.room_clear_tolerance,
                  "RMS sRGB difference between the room's colour and the pixel at which --room-clear stops")
      ->capture_default_str();
  cmd->add_option("--subject-explains", room.subject_explains,
                  "with the room model: the clearing stops where the subject's render is this much (RMS "
                  "sRGB) nearer the pixel than the room's colour alone (0 = off)")
      ->capture_default_str();
  cmd->add_option("--lean-gate", room.lean_gate,
                  "with the room model and a head box: in the head volume beyond the bare head, the "
                  "clearing's gate is at least this (1: always clear there; 0 = off)")
      ->capture_default_str();
  cmd->add_option("--solid-pull", room.solid_pull,
                  "with the room model and a head box: rays through the head's certain interior are the "
                  "subject's (no clearing), and that interior is pulled opaque with this many times the "
                  "opacity prior's weight (0 = off)")
      ->capture_default_str();
  cmd->add_option("--solid-reach", room.solid_reach_mm,
                  "with the room model and a head box: a ray that passes within this many mm of the head's "
                  "certain interior counts as crossing it (no clearing; the pull stays in the interior)")
      ->capture_default_str();
  cmd->add_option("--neck-clear", room.neck_clear,
                  "with the room model and a head box: in the neck's zone, rays whose pixel's chromaticity "
                  "lies further than this from every skin colour sampled on the face get the room-explained "
                  "clearing (0 = off)")
      ->capture_default_str();
  cmd->add_option("--room-first", room.room_first,
                  "with the room model: steps the room model trains alone first, on the rays that miss the "
                  "subject's volume (0 = off)")
      ->capture_default_str();
  cmd->add_option(
         "--keep-pull", room.keep_pull,
         "with the room model and a head box: in the neck's zone, the samples within --solid-reach of "
         "the neck's core are pulled towards opaque with this many times the opacity prior's weight "
         "(0 = off)")
      ->capture_default_str();
  cmd->add_option("--keep-far", room.keep_far_mm,
                  "with the room model and a head box: in the neck's zone, rays whose room colour comes from "
                  "further than this many mm beyond the subject's box (a wall, not the body) get the "
                  "room-explained clearing whatever their pixel's colour (0 = off)")
      ->capture_default_str();
  cmd->add_option("--keep-far-neck", room.keep_far_neck_mm,
                  "with --keep-far, before a wall beside the neck that may be skin: below the head box only "
                  "the room's colour within this many mm of the neck's axis counts as the body's; the "
                  "shoulders beside it are the room's (0 = the whole grown box)")
      ->capture_default_str();
}

void add_train(CLI::App& app, GlobalOptions& global) {
  auto* cmd = app.add_subcommand("train", "train a NeRF on a dataset (transforms.json or NeRF-synthetic)");
  auto a = std::make_shared<TrainArgs>();
  cmd->add_option("DATA", a->data, "dataset directory or json file")->required();
  cmd->add_option("-o,--output", a->settings.output, "model file to write (.lnerf)")->required();
  a->steps_given =
      cmd->add_option("--steps", a->steps,
                      "training steps, 1..1e7 (default: from the model's size, the same on every device)");
  a->seconds_given =
      cmd->add_option("--seconds", a->seconds,
                      "train for this wall-clock time (0.1 s .. a week) instead of a step count")
          ->excludes(a->steps_given);
  cmd->add_option("--seed", a->settings.seed, "random seed");
  cmd->add_flag("--deterministic", a->settings.deterministic,
                "bitwise reproducible (same seed, same device)");
  cmd->add_flag("--force", a->force, "overwrite an existing model file");
  cmd->add_flag("--resume", a->settings.resume,
                "continue from the training checkpoint beside the output (OUTPUT.ckpt, written with every "
                "snapshot) when there is one; it must be of the same data and settings");
  cmd->add_option("--batch-log2", a->settings.batch_log2,
                  "log2 of the samples per step, 10..22 (default: 18 on a GPU, 16 otherwise)");
  cmd->add_option("--lr", a->settings.lr, "base learning rate (default 1e-2)");
  cmd->add_option("--aabb", a->aabb, "bounding box minx,miny,minz,maxx,maxy,maxz (scene units)");
  cmd->add_option("--box", a->settings.box,
                  "subject box: auto (dataset aabb, else mask hull, else head box from landmarks, else "
                  "cameras), dataset, masks, head or cameras (default auto; --aabb overrides)")
      ->check(CLI::IsMember({"auto", "dataset", "masks", "head", "cameras"}));  // before loading the data
  a->hair_mm = fit::HeadExtents{}.hair_mm;  // shown as the default; only a given value is passed on
  a->hair_given =
      cmd->add_option(
             "--hair", a->hair_mm,
             "head box: millimetres of hair (or a hat) above and behind a large skull, and half of what "
             "exceeds the default 30 at its sides; the subject is cut where it stands out further (about "
             "40 mm more). Raise it for a bun, tall hair or a hat")
          ->capture_default_str();
  cmd->add_option("--background", a->settings.background,
                  "room model behind the subject, then keep the subject's connected region: auto (mask-less "
                  "datasets with a subject box), on or off")
      ->check(CLI::IsMember({"auto", "on", "off"}));
  add_room_options(cmd, a->settings.room);
  cmd->add_option("--aabb-scale", a->settings.aabb_scale,
                  "box size factor for datasets without alpha, 0.01..128 (default: dataset)");
  // Every number's range is checked by nerf::validate (host/util/bounds.h), with the same message
  // Python gives; --help states the ranges.
  cmd->add_option("--finest-res", a->settings.finest_res, "finest hash-grid resolution (16..1048576)");
  cmd->add_option("--log2-table", a->settings.log2_table, "log2 of the hash-table size per level (8..24)");
  cmd->add_option("--levels", a->settings.levels, "hash-grid levels (1..32)");
  cmd->add_option("--occ-res", a->settings.occ_res, "occupancy grid resolution (8..512)");
  cmd->add_option("--step", a->settings.step,
                  "marching step in scene units (default: the box's diagonal / 512; it must give 8..16384 "
                  "steps across it)");
  cmd->add_option("--downscale", a->settings.downscale, "integer image downscale factor, 1..16");
  cmd->add_option("--max-side", a->settings.max_side,
                  fmt::format("shrink images so the longer side is at most this (images that would hold "
                              "more than {:.1f} GB in memory shrink on their own, with a warning)",
                              nerf::kTrainImageBytes / 1e9));
  cmd->add_flag("--no-masks", a->no_masks, "ignore alpha masks when sizing the box");
  cmd->add_flag("--linear-loss", a->settings.linear_loss, "L2 on linear instead of sRGB colour");
  cmd->add_option("--snapshot-every", a->settings.snapshot_every,
                  "seconds between snapshots and training checkpoints (OUTPUT.ckpt; 0: only at the end)");
  cmd->callback([a, &global] { run_train(*a, global); });
}

}  // namespace
LGN_REGISTER_COMMAND(20, add_train);
}  // namespace lorgnette::cli
