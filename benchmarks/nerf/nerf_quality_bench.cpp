// Held-out PSNR against training seconds (and samples/s) for one dataset and one model
// configuration: trains with the library's Trainer, pausing the clock at checkpoints to evaluate a
// fixed subset of held-out views. Writes <out>/<label>_quality.csv (seconds, steps, samples,
// samples_per_s, psnr, ssim, mb) and <out>/<label>_quality.png; prints the final row as JSON.
// The model-size study runs it once per configuration (see docs/bench/nerf.md).
#include <fmt/format.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "host/dataset/dataset.h"
#include "host/nerf/sizing.h"
#include "host/nerf/trainer.h"
#include "host/render/evaluate.h"
#include "host/util/chart.h"

using namespace lorgnette;

int main(int argc, char** argv) {
  CLI::App app{"NeRF quality vs training time"};
  std::string data, out = "bench-out", label = "auto", device;
  double seconds = 300, eval_every = 60;
  uint32_t eval_views = 5, batch_log2 = 16, log2_table = 0, finest = 0, max_side = 0;
  app.add_option("--data", data)->required();
  app.add_option("--out", out);
  app.add_option("--label", label);
  app.add_option("--seconds", seconds);
  app.add_option("--eval-every", eval_every);
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
    nerf::ModelSizing sizing = nerf::choose_model_size(train, ov);
    spdlog::info("{}", sizing.summary());
    cl::Runtime rt({device, "", false});
    nerf::NerfModel model(rt, sizing.field, sizing.aabb, sizing.occupancy_resolution, sizing.step,
                          1u << batch_log2, 1337, false);
    nerf::TrainOptions to;
    to.seconds = seconds;
    to.progress = false;
    nerf::Trainer trainer(model, train, to, sizing.occupancy_mask);
    render::EvalOptions eo;
    eo.max_views = eval_views;
    std::vector<std::vector<std::string>> rows;
    ChartSeries series{label + " (" + fmt::format("{:.1f} MB", sizing.megabytes()) + ")", {}, {}};
    double trained = 0.0, next_eval = std::min(eval_every, seconds);
    nlohmann::json last;
    while (true) {
      auto t0 = std::chrono::steady_clock::now();
      while (trained < next_eval) {
        trainer.set_elapsed(trained);
        trainer.advance();  // one host synchronisation per step, as `train` runs
        trained += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        t0 = std::chrono::steady_clock::now();
      }
      render::EvalResult e = render::evaluate(model, test, eo);
      double sps = double(trainer.samples_done()) / trained;
      rows.push_back({fmt::format("{:.1f}", trained), std::to_string(trainer.steps_done()),
                      std::to_string(trainer.samples_done()), fmt::format("{:.0f}", sps),
                      fmt::format("{:.3f}", e.psnr), fmt::format("{:.4f}", e.ssim),
                      fmt::format("{:.2f}", sizing.megabytes())});
      series.x.push_back(trained);
      series.y.push_back(e.psnr);
      last = {{"label", label},           {"seconds", trained},   {"steps", trainer.steps_done()},
              {"samples_per_s", sps},     {"psnr", e.psnr},       {"ssim", e.ssim},
              {"mb", sizing.megabytes()}, {"eval_views", e.views}};
      spdlog::info("{}", last.dump());
      if (trained >= seconds) break;
      next_eval = std::min(seconds, next_eval + eval_every);
    }
    std::filesystem::create_directories(out);
    write_csv(out + "/" + label + "_quality.csv",
              {"seconds", "steps", "samples", "samples_per_s", "psnr", "ssim", "mb"}, rows);
    write_chart(out + "/" + label + "_quality.png",
                {"held-out PSNR vs training time (" + std::filesystem::path(data).filename().string() + ")",
                 "training seconds", "PSNR (dB)"},
                {series});
    std::cout << last.dump() << "\n";
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
