// What the room model costs (issue 13): on one synthetic room capture (`lorgnette synth --room`),
// two models of the same size, box and seed are trained side by side in one process, with the room
// model (`train --background on`, planned as `train` plans it: nerf::plan_training, with the head
// volume and its clearing zones) and without it (`off`, the head box alone: training before issue
// 13) at the same hash-table size, in alternating chunks of steps (the order swapped every chunk)
// so that machine load hits both alike. After each chunk both are scored on the held-out views
// against the true mattes (host/render/matte_eval.h: face PSNR, IoU, leak; the room model's subject
// region applied to a copy).
// Reports seconds per step of each, their ratio, and how many steps "on" needs to reach the face
// PSNR "off" ends with (linear between checkpoints), hence the training time at equal face quality.
// The face PSNR compared is over the face hull's pixels the subject covers fully
// (MatteScore::face_psnr_subject): the whole hull's rim holds room beside the jaw, which "off" paints
// on its box and "on" renders clear, so the whole hull (face_psnr_db, also written) favours "off".
// For each arm at its own product size and budget, see bench_room_budget.
// 2^16 samples per step (the CPU default of `train`).
// Usage: bench_room_cost DATASET OUT_DIR [--steps 1200] [--every 100] [--seed 1337] [--save-on MODEL]
// --save-on keeps the model trained with the room model (its subject region applied, as `train` does).
// Writes OUT_DIR/room_cost.csv (a row per model and checkpoint), room_cost_summary.csv and
// room_cost.png (face PSNR of the covered region against steps).
#include <fmt/format.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "capture/subject_box.h"
#include "host/dataset/dataset.h"
#include "host/nerf/subject_region.h"
#include "host/nerf/train_job.h"
#include "host/render/matte_eval.h"
#include "host/render/renderer.h"
#include "host/util/chart.h"
#include "synth/matte.h"

using namespace lorgnette;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

struct HeldOut {
  const dataset::Frame* frame = nullptr;
  Image matte, depth;
};

struct Arm {
  std::string name;
  std::unique_ptr<nerf::NerfModel> model;
  std::unique_ptr<nerf::Trainer> trainer;
  double seconds = 0.0;
  std::vector<double> chunk_seconds;
};

render::MatteScore score(nerf::NerfModel& model, bool region, const std::vector<HeldOut>& held,
                         const std::vector<Eigen::Vector3f>& face, render::Renderer& renderer) {
  const nerf::OccupancyGrid saved = model.occupancy();
  if (region) {
    nerf::OccupancyGrid g = saved;
    if (nerf::keep_central_region(g).found) model.set_occupancy(std::move(g));
  }
  std::vector<render::MatteScore> scores;
  for (const HeldOut& h : held) {
    Image pred = renderer.render(model, h.frame->camera, nullptr, render::RenderOptions{}).rgba;
    render::MatteView v{h.frame->camera, &pred, &h.frame->image, &h.matte, &h.depth, face};
    scores.push_back(render::score_matte(v, model.aabb()));
  }
  model.set_occupancy(saved);
  return render::mean_score(scores);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: bench_room_cost DATASET OUT_DIR [--steps 1200] [--every 100] [--seed 1337]\n";
    return 2;
  }
  const std::string data = argv[1], out = argv[2];
  uint64_t steps = 1200, every = 100;
  uint32_t seed = 1337;
  std::string save_on;
  for (int i = 3; i < argc; ++i) {
    if (std::strcmp(argv[i], "--steps") == 0 && i + 1 < argc)
      steps = std::stoull(argv[++i]);
    else if (std::strcmp(argv[i], "--every") == 0 && i + 1 < argc)
      every = std::stoull(argv[++i]);
    else if (std::strcmp(argv[i], "--seed") == 0 && i + 1 < argc)
      seed = uint32_t(std::stoul(argv[++i]));
    else if (std::strcmp(argv[i], "--save-on") == 0 && i + 1 < argc)
      save_on = argv[++i];
    else
      return std::cerr << "unknown argument " << argv[i] << "\n", 2;
  }
  if (every == 0 || steps % every) return std::cerr << "--steps must be a multiple of --every (> 0)\n", 2;
  fs::create_directories(out);
  cl::Runtime rt;
  dataset::Dataset ds = dataset::load_dataset(data, {});
  nerf::TrainJob job;
  capture::apply_subject_box(ds, capture::BoxSource::Auto, true, job);
  job.train.steps = steps;
  job.train.seed = seed;
  job.train.progress = false;
  job.batch_log2 = 16;
  std::vector<nerf::View> views = nerf::training_views(ds);
  nerf::TrainPlan plans[2];
  for (int k = 0; k < 2; ++k) {
    nerf::TrainJob j = job;
    j.background = k == 0 ? "on" : "off";
    if (k == 1) j.sizing.log2_table_size = plans[0].sizing.field.log2_table_size;  // the same size
    plans[k] = nerf::plan_training(rt, ds, views, j);
  }

  // Held-out views with their true mattes, subject depth and the 68 landmarks (face region).
  nlohmann::json gt = nlohmann::json::parse(std::ifstream(data + "/ground_truth.json"));
  const std::map<std::string, synth::EvalFiles> by_stem = synth::eval_files_by_stem(data);
  if (by_stem.empty()) return std::cerr << data << " has no true mattes: make it with synth --room\n", 1;
  std::vector<Eigen::Vector3f> face;
  for (const auto& p : gt.at("ibug68"))
    face.emplace_back(p[0].get<float>(), p[1].get<float>(), p[2].get<float>());
  if (face.empty())
    return std::cerr
               << data
               << " has no true landmarks (ibug68), hence no face region: use a procedural-head capture\n",
           1;
  std::vector<HeldOut> held;
  for (const dataset::Frame* f : ds.require_split(dataset::Split::Holdout)) {
    auto it = by_stem.at(fs::path(f->image_path).stem().string());
    held.push_back({f, synth::read_matte(data + "/" + it.matte), read_image(data + "/" + it.depth)});
  }

  Arm arms[2];
  for (int k = 0; k < 2; ++k) {
    arms[k].name = k == 0 ? "on" : "off";
    arms[k].model = std::make_unique<nerf::NerfModel>(nerf::planned_model(rt, ds, views, plans[k], job));
    arms[k].trainer = std::make_unique<nerf::Trainer>(*arms[k].model, views, plans[k].train,
                                                      plans[k].sizing.occupancy_mask);
  }
  render::Renderer renderer(rt);
  std::vector<std::vector<std::string>> rows;
  ChartSeries psnr[2];
  for (uint64_t done = 0; done < steps; done += every) {
    for (int j = 0; j < 2; ++j) {
      Arm& a = arms[(j + done / every) % 2];  // alternate which arm goes first
      auto t0 = Clock::now();
      for (uint64_t s = 0; s < every; ++s) a.trainer->step();
      const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
      a.seconds += dt;
      a.chunk_seconds.push_back(dt / double(every));
    }
    for (int k = 0; k < 2; ++k) {
      render::MatteScore m = score(*arms[k].model, k == 0, held, face, renderer);
      const uint64_t at = done + every;
      std::cerr << fmt::format(
          "{} step {}: face PSNR {:.2f} dB (covered {:.2f}), IoU {:.3f}, leak {:.1f} %, {:.3f} s/step, "
          "{:.0f} s\n",
          arms[k].name, at, m.face_psnr, m.face_psnr_subject, m.iou, 100 * m.leak,
          arms[k].chunk_seconds.back(), arms[k].seconds);
      rows.push_back({arms[k].name, std::to_string(at), fmt::format("{:.3f}", m.face_psnr),
                      fmt::format("{:.3f}", m.face_psnr_subject), fmt::format("{:.4f}", m.iou),
                      fmt::format("{:.4f}", m.leak), fmt::format("{:.4f}", arms[k].chunk_seconds.back()),
                      fmt::format("{:.1f}", arms[k].seconds)});
      psnr[k].name = "room model " + arms[k].name;
      psnr[k].x.push_back(double(at)), psnr[k].y.push_back(m.face_psnr_subject);
    }
    write_csv(out + "/room_cost.csv",
              {"room_model", "step", "face_psnr_db", "covered_face_psnr_db", "iou", "leak",
               "seconds_per_step_chunk", "seconds_total"},
              rows);
  }
  write_chart(out + "/room_cost.png",
              {"Face PSNR (covered by the subject) on held-out views against training steps", "step", "dB"},
              {psnr[0], psnr[1]});
  // Ratios of matching chunks (the same load), their median; steps for "on" to reach off's final PSNR.
  std::vector<double> ratio;
  for (size_t i = 0; i < arms[0].chunk_seconds.size(); ++i)
    ratio.push_back(arms[0].chunk_seconds[i] / arms[1].chunk_seconds[i]);
  std::sort(ratio.begin(), ratio.end());
  const double median_ratio = ratio[ratio.size() / 2];
  const double target = psnr[1].y.back();
  double reach = -1.0;
  for (size_t i = 0; i < psnr[0].y.size(); ++i)
    if (psnr[0].y[i] >= target) {
      if (i == 0) {
        reach = psnr[0].x[0];
      } else {
        const double y0 = psnr[0].y[i - 1], y1 = psnr[0].y[i];
        reach = psnr[0].x[i - 1] + (target - y0) / (y1 - y0) * (psnr[0].x[i] - psnr[0].x[i - 1]);
      }
      break;
    }
  const double time_ratio = reach > 0 ? median_ratio * reach / double(steps) : -1.0;
  std::cerr << fmt::format(
      "seconds per step: on {:.3f}, off {:.3f} (median chunk ratio {:.3f}); off ends at {:.2f} dB face PSNR "
      "after {} steps; on reaches it after {} steps; training time at equal face quality: {}\n",
      arms[0].seconds / steps, arms[1].seconds / steps, median_ratio, target, steps,
      reach > 0 ? fmt::format("{:.0f}", reach) : "never",
      time_ratio > 0 ? fmt::format("{:.2f} x", time_ratio) : "n/a");
  write_csv(
      out + "/room_cost_summary.csv",
      {"steps", "seconds_per_step_on", "seconds_per_step_off", "median_chunk_ratio", "off_final_face_psnr",
       "on_final_face_psnr", "on_steps_to_off_final", "time_ratio_at_equal_face_psnr"},
      {{std::to_string(steps), fmt::format("{:.4f}", arms[0].seconds / steps),
        fmt::format("{:.4f}", arms[1].seconds / steps), fmt::format("{:.4f}", median_ratio),
        fmt::format("{:.3f}", target), fmt::format("{:.3f}", psnr[0].y.back()),
        reach > 0 ? fmt::format("{:.0f}", reach) : "never",
        time_ratio > 0 ? fmt::format("{:.3f}", time_ratio) : "n/a"}});
  if (!save_on.empty()) {
    nerf::NerfModel& m = *arms[0].model;
    nerf::OccupancyGrid g = m.occupancy();
    std::cerr << nerf::keep_central_region(g).summary() << "\n";
    m.set_occupancy(std::move(g));
    m.metadata.dataset_path = fs::absolute(ds.root).string();
    m.metadata.dataset_hash = nerf::dataset_fingerprint(ds);
    m.metadata.device = rt.device().name;
    m.metadata.steps = steps;
    m.metadata.train_seconds = arms[0].seconds;
    m.metadata.seed = seed;
    m.save(save_on);
  }
  return 0;
}
