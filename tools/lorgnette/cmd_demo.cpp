// `lorgnette demo [-o DIR] [--glasses FRAME] [--quick]`: the whole try-on on a procedural head
// (demo/pipeline.h does the work).
#include <spdlog/spdlog.h>

#include <iostream>
#include <memory>

#include "demo/pipeline.h"
#include "tools/lorgnette/command.h"

namespace lorgnette::cli {
namespace {

void add_demo(CLI::App& app, GlobalOptions& global) {
  auto o = std::make_shared<demo::DemoOptions>();
  auto* cmd = app.add_subcommand("demo", "synthesize a head, train its NeRF, fit a frame, render an orbit");
  cmd->add_option("-o,--output", o->out_dir, "output directory")->capture_default_str();
  cmd->add_option("--glasses", o->glasses, "glasses file (default: a parametric 52-18-140 frame)")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--quick", o->quick, "the short variant (about 2 minutes on 2 CPU cores)");
  cmd->add_flag("--force", o->force, "replace an earlier demo output in the output directory");
  cmd->add_option("--seed", o->seed, "head shape, cameras and training seed")->capture_default_str();
  cmd->add_option("--views", o->views, "dataset views (default 48, quick 32)");
  cmd->add_option("--image-size", o->image_size, "dataset image size in pixels (default 192, quick 128)");
  auto* steps = cmd->add_option("--train-steps", o->train_steps,
                                "training steps (default: from the model's size, about 2000; quick 600)");
  cmd->add_option("--train-seconds", o->train_seconds,
                  "train for this wall-clock time instead of a step count")
      ->excludes(steps);
  cmd->add_option("--orbit-frames", o->orbit_frames, "orbit frames (default 36, quick 8)");
  cmd->add_option("--orbit-size", o->orbit_size, "orbit image size (default 320, quick 192)");
  cmd->add_option("--fit-views", o->fit_views, "views rendered for the fit (default 12, quick 8)");
  cmd->callback([o, &global] {
    o->progress = !global.quiet;
    demo::DemoReport r = demo::run_demo(*o, global.runtime());
    std::cerr << (r.ok ? "demo finished: " : "demo finished with problems: ") << o->out_dir
              << "/report.html (held-out PSNR " << r.psnr << " dB)\n";
    if (r.ok)
      std::cerr << "try it on in the browser: lorgnette view " << o->out_dir << "/head.lnerf --glasses "
                << (o->glasses.empty() ? o->out_dir + "/frame.glb" : o->glasses) << " --placement "
                << o->out_dir << "/placement.json\n";
    if (!r.ok) throw std::runtime_error(r.message);
  });
}

}  // namespace
LGN_REGISTER_COMMAND(5, add_demo);
}  // namespace lorgnette::cli
