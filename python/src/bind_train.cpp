// lorgnette.train: `lorgnette train` as a call (the same dataset loading, subject box, sizing and
// trainer), with the GIL released while it runs. A progress callable sees every step and stops
// training cleanly by returning False (the trainer's interrupt poll, host/util/interrupt.h: the
// snapshot is saved as after Ctrl-C); Ctrl-C in Python does the same and then raises KeyboardInterrupt.
#include <fmt/format.h>
#include <pybind11/stl.h>
#include <spdlog/spdlog.h>

#include <optional>

#include "capture/subject_box.h"
#include "host/dataset/dataset.h"
#include "host/nerf/train_job.h"
#include "host/util/interrupt.h"
#include "python/src/bindings.h"

namespace lorgnette::py {
namespace {

struct TrainArgs {
  std::string data, output, box = "auto", background = "auto";
  uint64_t steps = 0;
  double seconds = 0.0, hair_mm = fit::HeadExtents{}.hair_mm;
  uint32_t seed = 1337, batch_log2 = 0, max_side = 0, downscale = 1;
  bool deterministic = false, force = false, show_progress = false;
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
        if (!r.is_none() && !r.cast<bool>()) stopped = true;
      }
    } catch (pyb::error_already_set& e) {
      error = std::move(e);
      stopped = true;
    }
    if (stopped) request_interrupt();
  }
};

pyb::object run_train(const TrainArgs& a) {
  if (a.seconds < 0.0)
    throw pyb::value_error("seconds must be positive (or leave it out for the default budget)");
  if (a.steps > 0 && a.seconds > 0.0) throw pyb::value_error("give steps or seconds, not both");
  if (std::filesystem::exists(a.output) && !a.force)
    throw std::runtime_error("'" + a.output +
                             "' exists: pass force=True to overwrite it or choose another output");
  if (a.batch_log2 != 0 && (a.batch_log2 < 10 || a.batch_log2 > 22))
    throw pyb::value_error("batch_log2 must be 0 (by device: 18 on a GPU, 16 otherwise) or within 10..22");
  if (!(a.hair_mm >= 0.0 && a.hair_mm <= capture::kMaxHairMm))
    throw pyb::value_error(
        fmt::format("hair_mm must be within 0..{} (millimetres of hair or hat above and behind the skull)",
                    capture::kMaxHairMm));
  if (!std::filesystem::exists(a.data)) require_file(a.data, "dataset");
  auto model = std::make_shared<Model>();
  model->device = device_for(a.device);
  model->path = a.output;
  auto hook = std::make_shared<StepHook>();
  hook->fn = a.progress;
  nerf::TrainResult r;
  std::string budget;
  {
    pyb::gil_scoped_release release;
    dataset::LoadOptions lo;
    lo.downscale = int(a.downscale);
    lo.max_side = int(a.max_side);
    lo.max_image_bytes = nerf::kTrainImageBytes;
    lo.splits = {dataset::Split::Train};
    dataset::Dataset ds = dataset::load_dataset(a.data, lo);
    nerf::TrainJob job;
    fit::HeadBoxOptions head;
    head.extents.hair_mm = a.hair_mm;
    capture::apply_subject_box(ds, capture::box_source_from_string(a.box), true, job, head);
    job.batch_log2 = a.batch_log2;
    job.deterministic = a.deterministic;
    job.background = a.background;
    job.train.steps = a.steps;
    job.train.seconds = a.seconds;
    job.train.seed = a.seed;
    job.train.snapshot_path = a.output;
    job.train.progress = a.show_progress;
    job.train.on_step = [hook](uint64_t s, double t, double l) { (*hook)(s, t, l); };
    job.train.on_step_in_time = true;  // returning False at step k stops after step k
    std::lock_guard<std::mutex> lock(model->device->mutex);
    clear_interrupt();
    try {
      nerf::TrainJobResult out = nerf::train_on_dataset(model->device->runtime, ds, job);
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
  info["output"] = a.output;
  pyb::object m = pyb::cast(model);
  m.attr("train_info") = info;
  return m;
}

}  // namespace

void bind_train(pyb::module_& m) {
  m.def(
      "train",
      [](const std::string& data, const std::string& output, uint64_t steps, double seconds,
         pyb::object progress, uint32_t seed, uint32_t batch_log2, const std::string& box,
         const std::string& background, bool deterministic, uint32_t max_side, uint32_t downscale, bool force,
         bool show_progress, const std::string& device, double hair_mm) {
        TrainArgs a;
        a.data = data, a.output = output, a.steps = steps, a.seconds = seconds, a.progress = progress,
        a.seed = seed;
        a.batch_log2 = batch_log2, a.box = box, a.background = background, a.deterministic = deterministic;
        a.max_side = max_side, a.downscale = downscale, a.force = force, a.show_progress = show_progress;
        a.device = device, a.hair_mm = hair_mm;
        return run_train(a);
      },
      pyb::arg("dataset"), pyb::arg("output"), pyb::arg("steps") = 0, pyb::arg("seconds") = 0.0,
      pyb::arg("progress") = pyb::none(), pyb::arg("seed") = 1337, pyb::arg("batch_log2") = 0,
      pyb::arg("box") = "auto", pyb::arg("background") = "auto", pyb::arg("deterministic") = false,
      pyb::arg("max_side") = 0, pyb::arg("downscale") = 1, pyb::arg("force") = false,
      pyb::arg("show_progress") = false, pyb::arg("device") = "",
      pyb::arg("hair_mm") = fit::HeadExtents{}.hair_mm,
      "`lorgnette train DATASET -o OUTPUT`: trains and saves the snapshot, returns the Model (its "
      "`train_info` dict: steps, seconds, final_loss, stopped, budget, loss_curve). steps=0 and "
      "seconds=0: the size-based default budget. hair_mm: `--hair`, the head box's hair (or hat) above and "
      "behind the skull on a mask-less capture (the sides widen by half of what exceeds 30). Images that "
      "would hold more than 1.5 GB in memory are shrunk to fit (a warning says to what; max_side sets it). "
      "progress(step, seconds, loss) is called after every step (GIL held only then); returning False "
      "stops cleanly (the snapshot is saved, train_info['stopped']).");
}

}  // namespace lorgnette::py
