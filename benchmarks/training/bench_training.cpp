// Training throughput on any OpenCL device: a real training run (the library's Trainer on a
// dataset) is warmed up, then each timed step runs with every kernel launch recorded (LaunchLog
// on a profiling queue), so each kernel's device time, work-group count and samples/s come from
// the same steps as the step's wall time. The rest of the step (wall minus kernel time) is host
// work, transfers, fills and synchronisation. With --threads 1,2,... it re-runs itself once per
// PoCL thread count (POCL_MAX_PTHREAD_COUNT must be set before the OpenCL platform loads) and
// charts the scaling. Writes <out>/training_kernels.csv and, with --threads, one such folder per
// count (<out>/threads-N) and <out>/training_scaling.csv, training_scaling.png (M samples/s by
// stage) and training_speedup.png (wall-clock speedup by stage against the ideal).
// --as-train trains what `lorgnette train` trains on the dataset (on a mask-less capture: the room
// model too, whose launches add to the same kernels' rows); --float-add cas times the hash
// backward's compare-and-swap add where the device has its own (NVIDIA), for the side by side;
// --grad-groups 128 times the GPU MLP weight gradient with the old fixed split beside the split
// from the compute units.
#include <fmt/format.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "capture/subject_box.h"
#include "host/cl/launch_log.h"
#include "host/dataset/dataset.h"
#include "host/nerf/sizing.h"
#include "host/nerf/train_job.h"
#include "host/nerf/trainer.h"
#include "host/util/chart.h"
#include "host/util/machine.h"

using namespace lorgnette;

namespace {

// The stage of a training step each kernel belongs to.
std::string stage_of(const std::string& k) {
  static const std::map<std::string, std::string> stages = {{"sample_count", "sampling"},
                                                            {"sample_write", "sampling"},
                                                            {"sample_offsets", "sampling"},
                                                            {"loss_sum", "loss"},
                                                            {"hashgrid_encode", "hash forward"},
                                                            {"mlp_sh_encode", "MLP forward"},
                                                            {"mlp_chain_forward", "MLP forward"},
                                                            {"mlp_chain_forward_local", "MLP forward"},
                                                            {"mlp_sigma", "MLP forward"},
                                                            {"render_loss", "loss"},
                                                            {"mlp_chain_backward", "MLP backward"},
                                                            {"mlp_chain_backward_local", "MLP backward"},
                                                            {"mlp_weight_grad_partial", "MLP backward"},
                                                            {"mlp_weight_grad_partial_tiled", "MLP backward"},
                                                            {"mlp_weight_grad_fold", "MLP backward"},
                                                            {"mlp_weight_grad_reduce", "MLP backward"},
                                                            {"hashgrid_backward", "hash backward"},
                                                            {"hashgrid_backward_atomic", "hash backward"},
                                                            {"adam_step", "Adam"}};
  auto it = stages.find(k);
  return it == stages.end() ? "other kernels" : it->second;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct Options {
  std::string data, out = "bench-out/training", device, variant = "auto", threads, float_add = "native";
  uint32_t batch_log2 = 16, max_side = 0, warmup = 40, steps = 12, grad_groups = 0;
  bool deterministic = false, as_train = false;
};

struct KernelRow {
  std::string kernel, stage;
  double launches = 0, groups = 0, items = 0, local = 0;  // per step (groups, items: per launch, max)
  std::vector<double> seconds;                            // per step
};

// One run on this process's device: rows of training_kernels.csv.
int run_once(const Options& o) {
  dataset::LoadOptions lo;
  lo.max_side = int(o.max_side);
  dataset::Dataset ds = dataset::load_dataset(o.data, lo);
  cl::RuntimeOptions ro;
  ro.device = o.device;
  ro.profiling = true;
  ro.native_float_add = o.float_add == "native";
  ro.mlp_grad_groups = o.grad_groups;
  cl::Runtime rt(ro);
  const field::KernelVariant variant = o.variant == "gpu"   ? field::KernelVariant::Gpu
                                       : o.variant == "cpu" ? field::KernelVariant::Cpu
                                                            : field::KernelVariant::Auto;
  // The model `train` would build: --as-train plans it as train does (the subject box from the
  // dataset, masks or landmarks; on a mask-less capture the room model and the head's volume), else
  // automatic sizing alone, as before.
  nerf::TrainJob job;
  job.batch_log2 = o.batch_log2;
  job.deterministic = o.deterministic;
  job.train.steps = o.warmup + o.steps;
  job.train.seed = 1337;
  job.train.progress = false;
  std::vector<nerf::View> train = nerf::training_views(ds);
  nerf::TrainPlan plan;
  if (o.as_train) {
    capture::apply_subject_box(ds, capture::BoxSource::Auto, true, job);
    plan = nerf::plan_training(rt, ds, train, job);
  } else {
    nerf::SizingOverrides ov;
    ov.aabb_scale = ds.aabb_scale;
    plan.sizing = nerf::choose_model_size(train, ov);
    plan.train = job.train;
  }
  const nerf::ModelSizing& sizing = plan.sizing;
  nerf::NerfModel model(rt, sizing.field, sizing.aabb, sizing.occupancy_resolution, sizing.step,
                        1u << o.batch_log2, 1337, o.deterministic, variant);
  nerf::Trainer trainer(model, train, plan.train, sizing.occupancy_mask);
  for (uint32_t s = 0; s < o.warmup; ++s) trainer.advance();
  rt.finish();

  std::map<std::string, KernelRow> rows;
  std::vector<double> wall, kernel_total, samples, cpu;
  for (uint32_t s = 0; s < o.steps; ++s) {
    const uint64_t before = trainer.samples_done();
    cl::LaunchLog log;
    const double c0 = process_cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    trainer.advance();
    rt.finish();
    wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    cpu.push_back(process_cpu_seconds() - c0);
    samples.push_back(double(trainer.samples_done() - before));
    std::map<std::string, double> step_seconds;
    double total = 0;
    for (const auto& l : log.take()) {
      KernelRow& r = rows[l.kernel];
      r.kernel = l.kernel;
      r.stage = stage_of(l.kernel);
      r.launches += 1.0 / o.steps;
      r.groups = std::max(r.groups, double(l.groups));
      r.items = std::max(r.items, double(l.items));
      r.local = double(l.local);
      step_seconds[l.kernel] += l.seconds;
      total += l.seconds;
    }
    for (auto& [k, r] : rows) r.seconds.push_back(step_seconds[k]);
    kernel_total.push_back(total);
  }
  const double n = median(samples), step_wall = median(wall);
  std::printf(
      "device: %s  variant: %s  float add: %s  MLP gradient groups: %s  room model: %s  "
      "POCL_MAX_PTHREAD_COUNT=%s\n",
      rt.device().summary().c_str(), o.variant.c_str(), rt.native_float_add() ? "native" : "compare-and-swap",
      o.grad_groups ? std::to_string(o.grad_groups).c_str() : "from the compute units",
      plan.train.background.enabled ? "yes" : "no",
      getenv("POCL_MAX_PTHREAD_COUNT") ? getenv("POCL_MAX_PTHREAD_COUNT") : "(unset)");
  std::printf("%-26s %-14s %8s %9s %9s %10s %12s\n", "kernel", "stage", "launches", "groups", "ms/step",
              "share", "Msamples/s");
  std::vector<std::vector<std::string>> csv;
  auto add = [&](const std::string& kernel, const std::string& stage, double launches, double groups,
                 double items, double local, double sec) {
    std::printf("%-26s %-14s %8.1f %9.0f %9.2f %9.1f%% %12.2f\n", kernel.c_str(), stage.c_str(), launches,
                groups, sec * 1e3, 100.0 * sec / step_wall, sec > 0 ? n / sec / 1e6 : 0.0);
    csv.push_back({kernel, stage, fmt::format("{:.2f}", launches), fmt::format("{:.0f}", groups),
                   fmt::format("{:.0f}", items), fmt::format("{:.0f}", local), fmt::format("{:.6f}", sec),
                   fmt::format("{:.4f}", sec / step_wall), fmt::format("{:.0f}", n),
                   fmt::format("{:.0f}", sec > 0 ? n / sec : 0.0)});
  };
  for (auto& [k, r] : rows) add(k, r.stage, r.launches, r.groups, r.items, r.local, median(r.seconds));
  const double kernels = median(kernel_total);
  add("(host+transfers+sync)", "host", 0, 0, 0, 0, std::max(0.0, step_wall - kernels));
  add("(step)", "step", 0, 0, 0, 0, step_wall);
  // The process CPU time of a step (PoCL's threads included) over the thread count: the step time
  // with the cores to itself, when other jobs share the machine.
  const char* threads_env = getenv("POCL_MAX_PTHREAD_COUNT");
  const double threads =
      threads_env ? std::max(1, std::atoi(threads_env)) : double(rt.device().compute_units);
  add("(step CPU time / threads)", "step_cpu", 0, 0, 0, 0, median(cpu) / threads);
  std::printf("samples/step %.0f  step %.2f ms  %.3f M samples/s  CPU %.2f s per wall s  load %s\n", n,
              step_wall * 1e3, n / step_wall / 1e6, median(cpu) / step_wall,
              [] {
                std::ifstream f("/proc/loadavg");
                std::string s;
                std::getline(f, s);
                return s;
              }()
                  .c_str());
  std::filesystem::create_directories(o.out);
  write_csv(o.out + "/training_kernels.csv",
            {"kernel", "stage", "launches_per_step", "work_groups", "work_items", "local_size",
             "seconds_per_step", "share_of_step", "samples_per_step", "samples_per_second"},
            csv);
  return 0;
}

// Re-runs this program once per thread count (fresh process: PoCL reads the variable at load)
// and merges the per-stage rates into the scaling CSV and chart.
int run_scaling(const Options& o, const std::string& self, const std::vector<std::string>& base_args) {
  std::vector<int> counts;
  std::stringstream ss(o.threads);
  for (std::string t; std::getline(ss, t, ',');) counts.push_back(std::stoi(t));
  std::map<std::string, ChartSeries> series;
  std::vector<std::vector<std::string>> csv;
  for (int t : counts) {
    const std::string dir = fmt::format("{}/threads-{}", o.out, t);
    pid_t pid = fork();
    if (pid == 0) {
      setenv("POCL_MAX_PTHREAD_COUNT", std::to_string(t).c_str(), 1);
      std::vector<std::string> args = base_args;
      args.push_back("--out");
      args.push_back(dir);
      std::vector<char*> argv{const_cast<char*>(self.c_str())};
      for (auto& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(self.c_str(), argv.data());
      _exit(127);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      std::fprintf(stderr, "error: the run with %d threads failed\n", t);
      return 1;
    }
    std::ifstream f(dir + "/training_kernels.csv");
    std::string line;
    std::getline(f, line);
    std::map<std::string, double> stage_sec;
    double samples = 0;
    while (std::getline(f, line)) {
      std::vector<std::string> c;
      std::stringstream ls(line);
      for (std::string x; std::getline(ls, x, ',');) c.push_back(x);
      if (c.size() < 10) continue;
      stage_sec[c[1]] += std::stod(c[6]);
      samples = std::stod(c[8]);
    }
    for (const auto& [stage, sec] : stage_sec) {
      ChartSeries& s = series[stage];
      s.name = stage;
      s.x.push_back(t);
      s.y.push_back(sec > 0 ? samples / sec / 1e6 : 0.0);
      csv.push_back({std::to_string(t), stage, fmt::format("{:.6f}", sec), fmt::format("{:.0f}", samples),
                     fmt::format("{:.0f}", sec > 0 ? samples / sec : 0.0)});
    }
  }
  write_csv(o.out + "/training_scaling.csv",
            {"threads", "stage", "seconds_per_step", "samples_per_step", "samples_per_second"}, csv);
  // Samples/s of each stage (host time and kernels outside the stages left out), and the speedup
  // over the first thread count against the ideal.
  std::vector<ChartSeries> rates, speedups;
  ChartSeries ideal{"ideal", {}, {}};
  for (int t : counts) {
    ideal.x.push_back(t);
    ideal.y.push_back(double(t) / counts.front());
  }
  speedups.push_back(ideal);
  for (auto& [k, cs] : series) {
    if (k == "host" || k == "other kernels") continue;
    ChartSeries r = cs;
    if (k == "step_cpu") r.name = "step (CPU time / threads)";
    rates.push_back(r);
    if (k == "step_cpu") continue;  // CPU time per thread: its "speedup" is not a wall-clock one
    ChartSeries sp{r.name, r.x, {}};
    for (double y : r.y) sp.y.push_back(r.y.front() > 0 ? y / r.y.front() : 0.0);
    speedups.push_back(sp);
  }
  write_chart(o.out + "/training_scaling.png",
              {"Training throughput by stage over PoCL threads (" + o.variant + " kernels)",
               "POCL_MAX_PTHREAD_COUNT", "M samples/s", false},
              rates);
  write_chart(o.out + "/training_speedup.png",
              {"Wall-clock speedup by stage over PoCL threads (" + o.variant + " kernels)",
               "POCL_MAX_PTHREAD_COUNT", "speedup", false},
              speedups);
  std::printf("wrote %s/training_scaling.csv, training_scaling.png and training_speedup.png\n",
              o.out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Training throughput per kernel and per step (and over PoCL thread counts)"};
  Options o;
  app.add_option("--data", o.data, "dataset folder (transforms.json)")->required();
  app.add_option("--out", o.out, "output folder");
  app.add_option("--device", o.device, "OpenCL device (index or name substring)");
  app.add_option("--variant", o.variant, "kernels: auto (by device type), cpu or gpu")
      ->check(CLI::IsMember({"auto", "cpu", "gpu"}));
  app.add_option("--batch-log2", o.batch_log2, "samples per step = 2^N")->check(CLI::Range(10, 22));
  app.add_option("--max-side", o.max_side, "downscale images to this longest side (0: as stored)");
  app.add_option("--warmup", o.warmup, "training steps before timing (the occupancy grid settles)");
  app.add_option("--steps", o.steps, "timed steps (medians reported)")->check(CLI::PositiveNumber);
  app.add_flag("--deterministic", o.deterministic, "deterministic reductions (as train --deterministic)");
  app.add_option("--float-add", o.float_add,
                 "atomic float add of the hash backward: native (the device's own where known: NVIDIA) "
                 "or cas (compare-and-swap everywhere)")
      ->check(CLI::IsMember({"native", "cas"}));
  app.add_option("--grad-groups", o.grad_groups,
                 "GPU MLP weight gradient: at most N work-groups per layer (0: 8 per compute unit; 128: the "
                 "old fixed split, for the side by side)");
  app.add_flag("--as-train", o.as_train,
               "plan the model as `lorgnette train` does (subject box; the room model on mask-less "
               "captures); its room model's launches join the same kernels' rows");
  app.add_option("--threads", o.threads, "PoCL thread counts, e.g. 1,2: one run each and a scaling chart");
  CLI11_PARSE(app, argc, argv);
  spdlog::set_default_logger(spdlog::stderr_color_mt("bench"));
  spdlog::set_level(spdlog::level::warn);
  try {
    if (!o.threads.empty()) {
      std::vector<std::string> args;
      for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--threads" || a == "--out") {
          ++i;
          continue;
        }
        if (a.rfind("--threads=", 0) == 0 || a.rfind("--out=", 0) == 0) continue;
        args.push_back(a);
      }
      return run_scaling(o, "/proc/self/exe", args);
    }
    return run_once(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
