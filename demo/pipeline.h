// `lorgnette demo`: the whole try-on on data Lorgnette makes itself — synthesise a procedural head
// into a posed dataset, train its NeRF, make a parametric frame (or load the given one), fit it on
// the NeRF from dlib landmarks, render an orbit of head + glasses, and write report.json/.html.
// The output is built in a staging folder beside -o and swapped in when complete (--force replaces
// only an earlier demo output, host/util/output_folder.h). A failed run's output, its report saying
// ok = false and why, is kept only where it replaces nothing; an earlier output stays whole.
#pragma once
#include <cstdint>
#include <string>

#include "demo/report.h"
#include "host/cl/runtime.h"

namespace lorgnette::demo {

struct DemoOptions {
  std::string out_dir = "demo-output";
  std::string glasses;  // empty: a parametric frame made by `glasses make` logic
  bool quick = false;   // the CI variant: smaller images, shorter training, fewer frames
  bool force = false;   // replace an earlier demo output in out_dir
  uint64_t seed = 7;    // head shape, cameras, training
  // Sizes; 0 = the default of the chosen variant (see defaults_for()).
  int views = 0, image_size = 0, orbit_frames = 0, orbit_size = 0, fit_views = 0;
  // Training budget: `train_steps` steps (0: the size-based default of host/nerf/train_budget.h),
  // or, when `train_seconds` > 0, that much wall-clock time instead.
  uint64_t train_steps = 0;
  double train_seconds = 0.0;
  bool progress = true;
};

// Fills every 0 field with the default of the full or quick variant.
DemoOptions defaults_for(DemoOptions options);

// Runs every stage; returns the report (also written to out_dir). Throws for problems found before
// anything was written (bad options, output folder not empty, holding an input, or not writable) and
// for a failed or interrupted run (see above for what is kept).
DemoReport run_demo(const DemoOptions& options, const cl::RuntimeOptions& runtime);

}  // namespace lorgnette::demo
