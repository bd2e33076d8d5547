// lorgnette.train: `lorgnette train` as a call (the same dataset loading, subject box, sizing and
// trainer), with the GIL released while it runs. A progress callable sees every step and stops
// training cleanly by returning False (the trainer's interrupt poll, host/util/interrupt.h: the
// snapshot is saved as after Ctrl-C); Ctrl-C in Python does the same and then raises KeyboardInterrupt.
#include <fmt/format.h>
#include <pybind11/stl.h>
#include <spdlog/spdlog.h>

#include <optional>

#include "capture/train_request.h"
#include "host/nerf/train_job.h"
#include "host/nerf/train_settings.h"
#include "host/util/bounds.h"
#include "host/util/interrupt.h"
#include "python/src/bindings.h"

namespace lorgnette::py {
namespace {

struct TrainArgs {
  std::string data;
  nerf::TrainSettings settings;  // checked by nerf::validate, as `lorgnette train` is
  bool force = false;
  pyb::object progress;
  std::string device;
};

// Stops the trainer at its next poll when the callable says so or raises, or on Ctrl-C.
struct StepHook {
  pyb::object fn;
  std::optional<pyb::error_already_set> error;
  bool stopped = false;

  void operator()(uint64_t step, double seconds, double loss) {
    if (stopped) return;
    pyb::gil_scoped_acquire gil;
    try {
      if (PyErr_CheckSignals() != 0) throw pyb::error_already_set();
      if (!fn.is_none()) {
        pyb::object r = fn(step, seconds, loss);
        if (!r.is_none()) {  // any object's truth, as Python's `if` reads it
          int truth = PyObject_IsTrue(r.ptr());
          if (truth < 0) throw pyb::error_already_set();
          if (truth == 0) stopped = true;
        }
      }
    } catch (pyb::error_already_set& e) {
      error = std::move(e);
      stopped = true;
    }
    if (stopped) request_interrupt();
  }
};

pyb::object run_train(const TrainArgs& a) {
  const nerf::TrainSettings& s = a.settings;
  nerf::validate(s);
  nerf::refuse_output_onto_dataset(s.output, a.data);
  nerf::refuse_overwrite(s, a.force, "force=True", "resume=True");
  if (!std::filesystem::exists(a.data)) require_file(a.data, "dataset");
  auto model = std::make_shared<Model>();
  model->device = device_for(a.device);
  model->path = s.output;
  auto hook = std::make_shared<StepHook>();
  hook->fn = a.progress;
  nerf::TrainResult r;
  std::string budget;
  {
    pyb::gil_scoped_release release;
    capture::TrainRequest req = capture::prepare_training(a.data, s);
    req.job.train.on_step = [hook](uint64_t st, double t, double l) { (*hook)(st, t, l); };
    req.job.train.on_step_in_time = true;  // returning False at step k stops after step k
    std::lock_guard<std::mutex> lock(model->device->mutex);
    clear_interrupt();
    try {
      nerf::TrainJobResult out = nerf::train_on_dataset(model->device->runtime, req.dataset, req.job);
      clear_interrupt();
      r = out.result;
      budget = out.budget;
      model->nerf = std::make_unique<nerf::NerfModel>(std::move(out.model));
    } catch (...) {
      clear_interrupt();
      throw;
    }
  }
  if (hook->error) {  // the callable raised or Ctrl-C: the snapshot is saved; re-raise it
    hook->error->restore();
    throw pyb::error_already_set();
  }
  pyb::dict info;
  info["steps"] = r.steps, info["seconds"] = r.seconds, info["samples"] = r.samples;
  info["final_loss"] = r.final_loss, info["stopped"] = r.interrupted, info["budget"] = budget;
  info["loss_curve"] = r.loss_curve;
  info["output"] = s.output;
  pyb::object m = pyb::cast(model);
  m.attr("train_info") = info;
  return m;
}

}  // namespace

void bind_train(pyb::module_& m) {
  m.def(
      "train",
      [](const std::string& data, const std::string& output, pyb::object steps, pyb::object seconds,
         pyb::object progress, pyb::object seed, pyb::object batch_log2, const std::string& box,
         const std::string& background, bool deterministic, pyb::object max_side, pyb::object downscale,
         bool force, bool show_progress, const std::string& device, pyb::object hair_mm, bool resume) {
        namespace b = bounds;
        TrainArgs a;
        nerf::TrainSettings& s = a.settings;
        a.data = data, s.output = output, a.progress = progress, a.force = force, a.device = device;
        if (!steps.is_none()) s.steps = count_arg(steps, b::kTrainSteps);
        if (!seconds.is_none()) s.seconds = number_arg(seconds, b::kTrainSeconds);
        s.seed = uint32_t(count_arg(seed, {"--seed", "seed", 0, 4294967295.0, "random seed"}));
        s.batch_log2 = uint32_t(count_arg_or_zero(batch_log2, b::kBatchLog2));
        s.box = box, s.background = background, s.deterministic = deterministic;
        s.max_side = uint32_t(count_arg_or_zero(max_side, b::kMaxSide));
        s.downscale = uint32_t(count_arg(downscale, b::kDownscale));
        if (!hair_mm.is_none()) s.hair_mm = number_arg(hair_mm, b::kHairMm);
        s.progress = show_progress;
        s.resume = resume;
        return run_train(a);
      },
      pyb::arg("dataset"), pyb::arg("output"), pyb::arg("steps") = pyb::none(),
      pyb::arg("seconds") = pyb::none(), pyb::arg("progress") = pyb::none(), pyb::arg("seed") = 1337,
      pyb::arg("batch_log2") = 0, pyb::arg("box") = "auto", pyb::arg("background") = "auto",
      pyb::arg("deterministic") = false, pyb::arg("max_side") = 0, pyb::arg("downscale") = 1,
      pyb::arg("force") = false, pyb::arg("show_progress") = false, pyb::arg("device") = "",
      pyb::arg("hair_mm") = pyb::none(), pyb::arg("resume") = false,
      "`lorgnette train DATASET -o OUTPUT`: trains and saves the snapshot, returns the Model (its "
      "`train_info` dict: steps, seconds, final_loss, stopped, budget, loss_curve). steps (1..1e7) and "
      "seconds (0.1 .. a week) left out: the size-based default budget. hair_mm: `--hair` (0..300, default "
      "30), the head box's hair (or hat) above and behind the skull on a mask-less capture (the sides widen "
      "by half of what exceeds 30). Images that would hold more than 1.5 GB in memory are shrunk to fit (a "
      "warning says to what; max_side sets it). A number outside its range raises lorgnette.RangeError with "
      "the CLI's message. progress(step, seconds, loss) is called after every step (GIL held only then); "
      "returning False stops cleanly (the snapshot is saved, train_info['stopped']). The training checkpoint "
      "OUTPUT.ckpt (docs/file-formats.md) is written with the snapshots: resume=True continues a stopped "
      "training from it (same dataset and settings; `train --resume`).");
}

}  // namespace lorgnette::py
