// Field kernel throughput on the selected OpenCL device: the tiny MLP (forward and backward, in
// GFLOP/s of the logical network), the hash encoding (forward and backward, points/s), and a whole
// training step of the Field (forward + backward + Adam, samples/s) for several batch sizes.
// Writes field_bench.csv and field_bench.png into --out; prints one line per measurement.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/runtime.h"
#include "host/field/field.h"
#include "host/field/hashgrid.h"
#include "host/field/mlp.h"
#include "host/util/chart.h"
#include "host/util/machine.h"

using namespace lorgnette;
using namespace lorgnette::field;

namespace {

// Median wall seconds of `repeat` runs of fn (after one warm-up), each ended by a queue finish,
// and the mean process CPU seconds per run (PoCL's worker threads included): on a shared machine
// the CPU time shows what the kernels cost when the wall clock is inflated by other jobs.
struct Timing {
  double wall = 0, cpu = 0;
};
Timing time_it(cl::Runtime& rt, int repeat, const std::function<void()>& fn) {
  fn();
  rt.finish();
  std::vector<double> t;
  const double c0 = process_cpu_seconds();
  for (int r = 0; r < repeat; ++r) {
    auto t0 = std::chrono::steady_clock::now();
    fn();
    rt.finish();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(t.begin(), t.end());
  return {t[t.size() / 2], (process_cpu_seconds() - c0) / repeat};
}

std::vector<float> random_vector(size_t n, float lo, float hi, uint32_t seed) {
  std::mt19937 rng{seed};
  std::uniform_real_distribution<float> u(lo, hi);
  std::vector<float> v(n);
  for (float& x : v) x = u(rng);
  return v;
}

// Positions as NeRF training produces them: rays of 128 consecutive samples, Instant-NGP's step
// sqrt(3)/1024 apart, from random origins in random directions (wrapped into the unit cube).
std::vector<float> ray_positions(size_t S, uint32_t seed) {
  std::mt19937 rng{seed};
  std::uniform_real_distribution<float> u(0.0f, 1.0f), g(-1.0f, 1.0f);
  std::vector<float> p(3 * S);
  const float step = std::sqrt(3.0f) / 1024.0f;
  float o[3] = {0, 0, 0}, d[3] = {1, 0, 0};
  for (size_t i = 0; i < S; ++i) {
    if (i % 128 == 0) {
      float len = 0;
      do {
        for (float& x : d) x = g(rng);
        len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      } while (len < 0.1f || len > 1.0f);
      for (int a = 0; a < 3; ++a) {
        o[a] = u(rng);
        d[a] /= len;
      }
    }
    for (int a = 0; a < 3; ++a) {
      float x = o[a] + d[a] * step * float(i % 128);
      p[a * S + i] = x - std::floor(x);
    }
  }
  return p;
}

// Logical multiply-adds per sample of the Field's MLPs (no padding).
double mlp_macs(const ParamLayout& lay) {
  double m = 0;
  for (const auto& L : lay.density) m += double(L.in) * L.out;
  for (const auto& L : lay.color) m += double(L.in) * L.out;
  return m;
}

// One batch size's inputs: the Field, NeRF-like positions, unit directions and loss gradients.
struct Inputs {
  Inputs(cl::Runtime& rt, const FieldConfig& cfg, uint32_t n)
      : field(rt, cfg, n, 1, true),
        S(field.max_batch()),
        pos(rt, ray_positions(S, 1)),
        pos_random(rt, random_vector(3 * S, 0.0f, 1.0f, 1)),
        dir(rt, unit_directions(S)),
        sigma(rt, S),
        rgb(rt, 3 * S),
        dsig(rt, random_vector(S, -1.0f, 1.0f, 3)),
        drgb(rt, random_vector(3 * S, -1.0f, 1.0f, 4)) {}
  static std::vector<float> unit_directions(size_t S) {
    auto r = random_vector(3 * S, -1.0f, 1.0f, 2);
    std::vector<float> d(3 * S);
    for (size_t i = 0; i < S; ++i) {
      float l = std::sqrt(r[i] * r[i] + r[S + i] * r[S + i] + r[2 * S + i] * r[2 * S + i]) + 1e-6f;
      for (int a = 0; a < 3; ++a) d[a * S + i] = r[a * S + i] / l;
    }
    return d;
  }
  Field field;
  size_t S;
  cl::Buffer<float> pos, pos_random, dir, sigma, rgb, dsig, drgb;
};

class Bench {
 public:
  Bench(cl::Runtime& rt, int repeat)
      : rt_(rt), repeat_(repeat), cores_(std::max<uint32_t>(1, rt.device().compute_units)) {}

  void run(uint32_t n) {
    Inputs in(rt_, cfg_, n);
    hash(in, n);
    mlp(in, n);
    field(in, n);
  }
  void write(const std::string& out) const;

 private:
  void report(const std::string& what, uint32_t batch, const std::function<void()>& fn, double work,
              const std::string& unit) {
    const Timing t = time_it(rt_, repeat_, fn);
    rows_.push_back({what, batch, t, work / t.wall, work / (t.cpu / cores_), unit});
    const Row& r = rows_.back();
    std::printf("%-18s batch %7u  %9.2f ms  %9.2f %-10s (cpu %8.2f ms -> %9.2f %s with %g idle cores)\n",
                what.c_str(), batch, t.wall * 1e3, r.rate, unit.c_str(), t.cpu * 1e3, r.rate_cpu,
                unit.c_str(), cores_);
    std::fflush(stdout);
  }
  void hash(Inputs& in, uint32_t n);
  void mlp(Inputs& in, uint32_t n);
  void field(Inputs& in, uint32_t n);
  void chart(const std::string& path, const std::string& y_label,
             const std::vector<const char*>& whats) const;

  struct Row {
    std::string what;
    uint32_t batch;
    Timing t;
    double rate, rate_cpu;  // work / wall; work / (cpu / cores): the rate with the cores to itself
    std::string unit;
  };
  cl::Runtime& rt_;
  int repeat_;
  double cores_;
  FieldConfig cfg_;
  std::vector<Row> rows_;
};

void Bench::hash(Inputs& in, uint32_t n) {
  const ParamLayout& lay = in.field.layout();
  HashGrid grid(rt_, cfg_, lay, uint32_t(in.S));
  cl::Buffer<float> enc(rt_, lay.enc_pad * in.S),
      denc(rt_, random_vector(lay.enc_pad * in.S, -1.0f, 1.0f, 5));
  cl::Buffer<float>& params = in.field.params();
  cl::Buffer<float>& grads = in.field.gradients();
  report(
      "hash_forward", n, [&] { grid.encode(params, in.pos, n, enc); }, n / 1e6, "Mpoints/s");
  report(
      "hash_backward", n, [&] { grid.backward(in.pos, denc, n, grads, true); }, n / 1e6, "Mpoints/s");
  report(
      "hash_grad_zero", n, [&] { grads.fill(rt_, 0.0f, 0, lay.hash_count); }, lay.hash_count / 1e6,
      "Mfloats/s");
  report(
      "hash_fwd_random", n, [&] { grid.encode(params, in.pos_random, n, enc); }, n / 1e6, "Mpoints/s");
  report(
      "hash_bwd_random", n, [&] { grid.backward(in.pos_random, denc, n, grads, true); }, n / 1e6,
      "Mpoints/s");
}

// The Field's MLPs alone: layer by layer (one launch per layer) and as the fused chain the Field
// runs (all layers per 32-sample slab while its activations are in cache).
void Bench::mlp(Inputs& in, uint32_t n) {
  const ParamLayout& lay = in.field.layout();
  const size_t S = in.S;
  Mlp mlp(rt_, uint32_t(S));
  ChainPlan plan = plan_chain(lay, uint32_t(S));
  std::vector<const LayerShape*> layers = {&lay.density[0], &lay.density[1]};
  for (const auto& L : lay.color) layers.push_back(&L);
  const int count = int(layers.size());
  cl::Buffer<float> acts(rt_, random_vector(plan.rows * S, 0.0f, 1.0f, 9)),
      deltas(rt_, random_vector(plan.rows * S, -1.0f, 1.0f, 8));
  cl::Buffer<float> partial(rt_, size_t(mlp.max_grad_chunks()) * 256 * 256);
  cl::Buffer<float>& W = in.field.params();
  cl::Buffer<float>& G = in.field.gradients();
  const MlpChainParams& c = plan.chain;
  auto io = [&](int l) { return LayerIo{&acts, c.x_row[l], &deltas, c.dy_row[l]}; };
  const double gflop = 2.0 * mlp_macs(lay) * n / 1e9;
  report(
      "mlp_forward", n,
      [&] {
        for (int l = 0; l < count; ++l)
          mlp.forward(*layers[l], W, {&acts, c.x_row[l], &acts, c.y_row[l]}, n, c.act[l]);
      },
      gflop, "GFLOP/s");
  report(
      "mlp_backward", n,
      [&] {
        for (int l = count - 1; l >= 0; --l) {
          mlp.weight_grad(*layers[l], io(l), n, partial, G);
          mlp.backward_input(*layers[l], W, io(l), n, deltas, c.dx_row[l], c.k_begin[l], c.mask[l]);
        }
      },
      2 * gflop, "GFLOP/s");
  report(
      "mlp_weight_grad", n,
      [&] {
        for (int l = count - 1; l >= 0; --l) mlp.weight_grad(*layers[l], io(l), n, partial, G);
      },
      gflop, "GFLOP/s");
  report(
      "mlp_input_grad", n,
      [&] {
        for (int l = count - 1; l >= 0; --l)
          mlp.backward_input(*layers[l], W, io(l), n, deltas, c.dx_row[l], c.k_begin[l], c.mask[l]);
      },
      gflop, "GFLOP/s");
  report(
      "mlp_fused_fwd", n, [&] { mlp.chain_forward(c, n, W, acts); }, gflop, "GFLOP/s");
  report(
      "mlp_fused_bwd_data", n, [&] { mlp.chain_backward(c, n, W, acts, deltas, in.dsig, in.drgb); }, gflop,
      "GFLOP/s");
  report(
      "mlp_fused_bwd", n,
      [&] {
        mlp.chain_backward(c, n, W, acts, deltas, in.dsig, in.drgb);
        for (int l = 0; l < count; ++l) mlp.weight_grad(*layers[l], io(l), n, partial, G);
      },
      2 * gflop, "GFLOP/s");
}

void Bench::field(Inputs& in, uint32_t n) {
  Field& f = in.field;
  AdamConfig adam;
  report(
      "field_forward", n, [&] { f.forward(in.pos, in.dir, n, in.sigma, in.rgb, true); }, n / 1e6,
      "Msamples/s");
  report(
      "field_backward", n, [&] { f.backward(in.dsig, in.drgb, n); }, n / 1e6, "Msamples/s");
  // Inference (keep_for_backward = false): the fused kernel on CPUs (host/field/field_infer.h), the
  // same sigma and rgb as field_forward above, which is the path inference took before it.
  report(
      "field_inference", n, [&] { f.forward(in.pos, in.dir, n, in.sigma, in.rgb, false); }, n / 1e6,
      "Msamples/s");
  report(
      "adam", n, [&] { f.adam_step(adam); }, f.layout().total / 1e6, "Mparams/s");
  report(
      "train_step", n,
      [&] {
        f.forward(in.pos, in.dir, n, in.sigma, in.rgb, true);
        f.backward(in.dsig, in.drgb, n);
        f.adam_step(adam);
      },
      n / 1e6, "Msamples/s");
}

// Charts of the CPU-time rates (what the kernels do with the cores to themselves).
void Bench::chart(const std::string& path, const std::string& y_label,
                  const std::vector<const char*>& whats) const {
  std::vector<ChartSeries> series;
  for (const char* what : whats) {
    ChartSeries cs;
    cs.name = what;
    for (const Row& r : rows_)
      if (r.what == what) {
        cs.x.push_back(r.batch);
        cs.y.push_back(r.rate_cpu);
      }
    series.push_back(cs);
  }
  write_chart(path, {"Field kernels on " + rt_.device().name + " (CPU-time rate)", "batch", y_label, true},
              series);
}

void Bench::write(const std::string& out) const {
  std::vector<std::vector<std::string>> csv;
  for (const Row& r : rows_)
    csv.push_back({r.what, std::to_string(r.batch), fmt::format("{:.6f}", r.t.wall),
                   fmt::format("{:.6f}", r.t.cpu), fmt::format("{:.4f}", r.rate),
                   fmt::format("{:.4f}", r.rate_cpu), r.unit});
  write_csv(out + "/field_bench.csv",
            {"measurement", "batch", "wall_seconds", "cpu_seconds", "rate", "rate_idle_estimate", "unit"},
            csv);
  chart(out + "/field_bench_mlp.png", "GFLOP/s",
        {"mlp_forward", "mlp_backward", "mlp_fused_fwd", "mlp_fused_bwd"});
  chart(
      out + "/field_bench_rates.png", "M points or samples / s",
      {"hash_forward", "hash_backward", "field_forward", "field_inference", "field_backward", "train_step"});
  std::printf("wrote %s/field_bench.csv, field_bench_mlp.png, field_bench_rates.png\n", out.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Field kernel throughput benchmark");
  std::string out = "bench-out/field", device;
  std::vector<uint32_t> batches = {1u << 16, 1u << 17, 1u << 18};
  int repeat = 5;
  app.add_option("--out", out, "output directory for CSV and PNG");
  app.add_option("--device", device, "OpenCL device (index or name substring)");
  app.add_option("--batch", batches, "batch sizes");
  app.add_option("--repeat", repeat, "timed runs per measurement (median reported)")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  try {
    std::filesystem::create_directories(out);
    cl::Runtime rt({device, "", false});
    std::printf("device: %s\n", rt.device().summary().c_str());
    Bench bench(rt, repeat);
    for (uint32_t n : batches) bench.run(n);
    bench.write(out);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
