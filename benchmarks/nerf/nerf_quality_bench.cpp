// Held-out PSNR against training seconds (and samples/s) for one dataset and one model
// configuration: trains with the library's Trainer, pausing the clock at checkpoints to evaluate a
// fixed subset of held-out views. Writes <out>/<label>_quality.csv (seconds, steps, samples,
// samples_per_s, psnr, ssim, mb, cpu_s) and <out>/<label>_quality.png; prints the final row as JSON.
// --seconds S budgets wall time (the product's `--seconds`); --steps N budgets steps instead, with
// checkpoints every --eval-every-steps, and the learning-rate schedule then runs over the steps:
// step counts do not depend on the machine's load, so configurations compare at equal steps.
// cpu_s is the process's CPU time (PoCL's threads included) spent training, evaluations excluded.
// The model-size and per-step studies run it once per configuration (see docs/bench/nerf.md).
#include <fmt/format.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "host/dataset/dataset.h"
#include "host/nerf/sizing.h"
#include "host/nerf/trainer.h"
#include "host/render/evaluate.h"
#include "host/util/chart.h"
#include "host/util/machine.h"

using namespace lorgnette;

int main(int argc, char** argv) {
  CLI::App app{"NeRF quality vs training time"};
  std::string data, out = "bench-out", label = "auto", device;
  double seconds = 300, eval_every = 60;
  uint64_t steps = 0, eval_every_steps = 500;
  uint32_t eval_views = 5, batch_log2 = 16, log2_table = 0, finest = 0, max_side = 0, steps_per_diagonal = 0;
  nerf::TrainOptions to;
  app.add_option("--data", data)->required();
  app.add_option("--out", out);
  app.add_option("--label", label);
  app.add_option("--seconds", seconds, "wall-clock budget (ignored with --steps)");
  app.add_option("--eval-every", eval_every, "seconds between evaluations (with --seconds)");
  app.add_option("--steps", steps, "step budget instead of --seconds (0: use --seconds)");
  app.add_option("--eval-every-steps", eval_every_steps, "steps between evaluations (with --steps)")
      ->check(CLI::PositiveNumber);
  app.add_option("--lr", to.adam.lr, "base learning rate");
  app.add_option("--decay-start", to.decay_start,
                 "fraction of the run where the learning rate starts to decay")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--final-lr", to.final_lr_fraction, "final learning rate as a fraction of the base")
      ->check(CLI::Range(1e-6, 1.0));
  app.add_option("--steps-per-diagonal", steps_per_diagonal, "marching step = box diagonal / this")
      ->check(CLI::Range(16u, 8192u));
  app.add_option("--eval-views", eval_views);
  app.add_option("--batch-log2", batch_log2);
  app.add_option("--log2-table", log2_table);
  app.add_option("--finest-res", finest);
  app.add_option("--max-side", max_side);
  app.add_option("--device", device);
  CLI11_PARSE(app, argc, argv);
  spdlog::set_default_logger(spdlog::stderr_color_mt("bench"));
  try {
    dataset::LoadOptions lo;
    lo.max_side = int(max_side);
    dataset::Dataset ds = dataset::load_dataset(data, lo);
    std::vector<nerf::View> train, test;
    for (const auto* f : ds.split(dataset::Split::Train)) train.push_back({f->camera, &f->image});
    for (const auto* f : ds.split(ds.default_eval_split())) test.push_back({f->camera, &f->image});
    nerf::SizingOverrides ov;
    ov.aabb_scale = ds.aabb_scale;
    if (log2_table) ov.log2_table_size = log2_table;
    if (finest) ov.finest_resolution = finest;
    if (steps_per_diagonal) ov.steps_per_diagonal = steps_per_diagonal;
    nerf::ModelSizing sizing = nerf::choose_model_size(train, ov);
    spdlog::info("{}", sizing.summary());
    cl::Runtime rt({device, "", false});
    nerf::NerfModel model(rt, sizing.field, sizing.aabb, sizing.occupancy_resolution, sizing.step,
                          1u << batch_log2, 1337, false);
    const bool by_steps = steps > 0;
    if (by_steps)
      to.steps = steps;
    else
      to.seconds = seconds;
    to.progress = false;
    spdlog::info("schedule: lr {} until {} of the {}, then down to {} of it", to.adam.lr, to.decay_start,
                 by_steps ? fmt::format("{} steps", steps) : fmt::format("{} s", seconds),
                 to.final_lr_fraction);
    nerf::Trainer trainer(model, train, to, sizing.occupancy_mask);
    render::EvalOptions eo;
    eo.max_views = eval_views;
    std::vector<std::vector<std::string>> rows;
    ChartSeries series{label + " (" + fmt::format("{:.1f} MB", sizing.megabytes()) + ")", {}, {}};
    double trained = 0.0, cpu = 0.0, next_eval = std::min(eval_every, seconds);
    uint64_t next_eval_step = std::min(eval_every_steps, steps);
    nlohmann::json last;
    std::filesystem::create_directories(out);
    while (true) {
      auto t0 = std::chrono::steady_clock::now();
      const double c0 = process_cpu_seconds();
      while (by_steps ? trainer.steps_done() < next_eval_step : trained < next_eval) {
        trainer.set_elapsed(trained);
        trainer.advance();  // one host synchronisation per step, as `train` runs
        trained += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        t0 = std::chrono::steady_clock::now();
      }
      trainer.last_loss();  // the last step's kernels finish inside the training time
      trained += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      cpu += process_cpu_seconds() - c0;
      render::EvalResult e = render::evaluate(model, test, eo);
      double sps = double(trainer.samples_done()) / trained;
      rows.push_back({fmt::format("{:.1f}", trained), std::to_string(trainer.steps_done()),
                      std::to_string(trainer.samples_done()), fmt::format("{:.0f}", sps),
                      fmt::format("{:.3f}", e.psnr), fmt::format("{:.4f}", e.ssim),
                      fmt::format("{:.2f}", sizing.megabytes()), fmt::format("{:.1f}", cpu)});
      series.x.push_back(by_steps ? double(trainer.steps_done()) : trained);
      series.y.push_back(e.psnr);
      last = {{"label", label},           {"seconds", trained},    {"steps", trainer.steps_done()},
              {"samples_per_s", sps},     {"psnr", e.psnr},        {"ssim", e.ssim},
              {"mb", sizing.megabytes()}, {"eval_views", e.views}, {"cpu_s", cpu}};
      spdlog::info("{}", last.dump());
      // After every checkpoint, so an interrupted long run keeps the rows it has.
      write_csv(out + "/" + label + "_quality.csv",
                {"seconds", "steps", "samples", "samples_per_s", "psnr", "ssim", "mb", "cpu_s"}, rows);
      if (by_steps ? trainer.steps_done() >= steps : trained >= seconds) break;
      next_eval = std::min(seconds, next_eval + eval_every);
      next_eval_step = std::min(steps, next_eval_step + eval_every_steps);
    }
    write_chart(out + "/" + label + "_quality.png",
                {"held-out PSNR vs training " + std::string(by_steps ? "steps" : "time") + " (" +
                     std::filesystem::path(data).filename().string() + ")",
                 by_steps ? "training steps" : "training seconds", "PSNR (dB)"},
                {series});
    std::cout << last.dump() << "\n";
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
