// The try-on service under load, on loopback: `lorgnette serve` as a real process, and N shoppers
// (threads) who each create a capture, upload the same synthetic head-turn video (`synth --room 1`
// encoded by ffmpeg, or --video), start it and poll its status until it ends, processed at a
// shop-wide training budget (short by default). Checks that every job finishes once, from three
// sources: what the shoppers saw (N distinct ids finished, one worker start each), the store (its
// counts by state: N finished, nothing else) and the data folder (N capture folders, each complete,
// and one "worker ended" line per job in the server's log). Writes into --out:
//   jobs.csv      per job, in the order the queue served them: upload, queue wait, capture / train /
//                 fit seconds (seen by polling every 0.25 s), the fit split into placement and try-on
//                 pictures (from the job folder's file times), total from start to end, attempts
//   jobs.png      those seconds per shopper, in the order the queue served them
//   summary.json  the totals, jobs per hour, the checks, the machine's load average during the run,
//                 requests per second on the status endpoint (keep-alive clients for
//                 --status-seconds), the server's memory (RSS) per open capture and the workers' peak
//                 memory, and the server's own /metrics stage histograms
// Usage: service_load_bench --out DIR [--shoppers 20] [--workers 1] [--train-steps 30] [--frames 0]
//        [--db postgresql://...] [--video FILE] [--capture-fps 0 --capture-max-side 0 (the defaults)]
#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "host/util/chart.h"
#include "service/child_process.h"

namespace fs = std::filesystem;
namespace beast = boost::beast;
namespace http = beast::http;
using lorgnette::service::ChildEnd;
using lorgnette::service::ChildProcess;
using Clock = std::chrono::steady_clock;

namespace {

const std::string kAdmin = "bench-admin-token-0123456789abcdef0123";

struct Args {
  std::string out, lorgnette = LGN_CLI_PATH, db, size = "256x192", video;
  int shoppers = 20, workers = 1, train_steps = 30, train_batch_log2 = 12, views = 16, frames = 0;
  int video_fps = 8, capture_max_side = 256, samples = 1;
  double capture_fps = 8.0;
  int status_clients = 4, idle_captures = 500;
  double status_seconds = 5.0, timeout_seconds = 3600.0;
};

// One keep-alive HTTP/1.1 connection to the server.
class Client {
 public:
  explicit Client(uint16_t port) : socket_(ioc_) {
    socket_.connect({boost::asio::ip::make_address("127.0.0.1"), port});
  }
  std::pair<int, std::string> request(http::verb verb, const std::string& target,
                                      const std::string& token = "", const std::string& body = "") {
    http::request<http::string_body> req{verb, target, 11};
    req.set(http::field::host, "127.0.0.1");
    if (!token.empty()) req.set(http::field::authorization, "Bearer " + token);
    req.body() = body;
    req.prepare_payload();
    http::write(socket_, req);
    http::response<http::string_body> res;
    http::read(socket_, buffer_, res);
    return {int(res.result_int()), res.body()};
  }

 private:
  boost::asio::io_context ioc_;
  boost::asio::ip::tcp::socket socket_;
  beast::flat_buffer buffer_;
};

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void run_or_throw(const std::vector<std::string>& argv, const fs::path& log) {
  ChildEnd e = ChildProcess(argv, log.string()).wait();
  if (!e.exited || e.code != 0) throw std::runtime_error(argv[0] + " failed; see " + log.string());
}

// kB of resident memory of process `pid` (VmRSS), 0 when it is gone.
double rss_kb(pid_t pid) {
  std::istringstream in(read_text(fmt::format("/proc/{}/status", pid)));
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6));
  return 0.0;
}

// The children of `pid` (the workers of the server), from /proc/<pid>/task/*/children.
std::vector<pid_t> children(pid_t pid) {
  std::vector<pid_t> out;
  std::error_code ec;
  for (auto it = fs::directory_iterator(fmt::format("/proc/{}/task", pid), ec);
       !ec && it != fs::directory_iterator(); ++it) {
    std::istringstream in(read_text(it->path() / "children"));
    for (pid_t c; in >> c;) out.push_back(c);
  }
  return out;
}

// The shoppers' video: --video when given, else `synth --room 1` encoded at --video-fps, output at 30
// frames per second as a phone writes it (each synthetic view repeated).
fs::path make_video(const Args& a) {
  const fs::path dir = fs::path(a.out) / "video";
  fs::create_directories(dir);
  if (!a.video.empty()) return a.video;
  run_or_throw(
      {a.lorgnette, "-q", "synth", "--procedural", "--room", "1", "--views", std::to_string(a.views),
       "--size", a.size, "--samples", std::to_string(a.samples), "-o", (dir / "room").string(), "--force"},
      dir / "synth.log");
  run_or_throw({"/usr/bin/ffmpeg", "-y", "-loglevel", "error", "-framerate", std::to_string(a.video_fps),
                "-i", (dir / "room/images/%04d.png").string(), "-r", "30", "-c:v", "libx264", "-pix_fmt",
                "yuv420p", (dir / "room.mp4").string()},
               dir / "ffmpeg.log");
  return dir / "room.mp4";
}

// N frames from `glasses make` (the same design under N names: each is fitted on its own).
fs::path make_catalogue(const Args& a) {
  const fs::path dir = fs::path(a.out) / "catalogue";
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (int i = 0; i < a.frames; ++i)
    run_or_throw(
        {a.lorgnette, "-q", "glasses", "make", "-o", (dir / fmt::format("frame{:02d}.glb", i)).string()},
        fs::path(a.out) / "video" / "glasses.log");
  return dir;
}

struct Job {
  std::string id, token, state, message;
  int attempts = 0;
  double upload_s = 0, queue_wait_s = 0, total_s = 0;
  std::map<std::string, double> stage_s;  // capture / train / fit
  bool ok = false;
  // From the job's folder after the run (check_folders): the fit stage split into the placement
  // (from the model file's time to placement.json's) and the try-on pictures (to views.json's).
  double fit_only_s = 0, tryon_s = 0;
  std::map<std::string, double> cpu_s;  // CPU seconds of its worker by stage (MemoryMonitor)
};

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// One shopper: create, upload, start, then poll every 0.25 s until the job ends.
Job shopper(uint16_t port, const std::string& video, double timeout_s) {
  Job j;
  Client c(port);
  auto [st, body] = c.request(http::verb::post, "/api/v1/captures", "", "{}");
  if (st != 201) throw std::runtime_error("create: " + std::to_string(st) + " " + body);
  auto created = nlohmann::json::parse(body);
  j.id = created["id"], j.token = created["token"];
  const std::string base = "/api/v1/captures/" + j.id;
  const auto t_up = Clock::now();
  if (auto [s, b] = c.request(http::verb::put, base + "/video", j.token, video); s != 201)
    throw std::runtime_error("upload: " + b);
  j.upload_s = since(t_up);
  const auto t0 = Clock::now();
  if (auto [s, b] = c.request(http::verb::post, base + "/start", j.token); s != 202)
    throw std::runtime_error("start: " + b);
  std::map<std::string, double> first_seen;
  double running_at = -1;
  nlohmann::json s;
  while (since(t0) < timeout_s) {
    s = nlohmann::json::parse(c.request(http::verb::get, base, j.token).second);
    const double t = since(t0);
    if (s["state"] == "running" && running_at < 0) running_at = t;
    const std::string stage = s["stage"];
    if (s["state"] == "running" && !stage.empty() && !first_seen.count(stage)) first_seen[stage] = t;
    if (s["state"] == "finished" || s["state"] == "failed") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
  }
  j.total_s = since(t0);
  j.state = s["state"], j.message = s["message"], j.attempts = s["attempts"];
  j.queue_wait_s = running_at < 0 ? j.total_s : running_at;
  const std::vector<std::string> order{"capture", "train", "fit"};
  for (size_t i = 0; i < order.size(); ++i) {
    if (!first_seen.count(order[i])) continue;
    double end = j.total_s;
    for (size_t k = i + 1; k < order.size(); ++k)
      if (first_seen.count(order[k])) {
        end = first_seen[order[k]];
        break;
      }
    j.stage_s[order[i]] = end - first_seen[order[i]];
  }
  j.ok = j.state == "finished";
  return j;
}

// Requests per second on one capture's status with `clients` keep-alive connections.
double status_rps(uint16_t port, const Job& j, int clients, double seconds) {
  std::atomic<long> ok{0};
  std::vector<std::thread> threads;
  const auto end = Clock::now() + std::chrono::duration<double>(seconds);
  for (int i = 0; i < clients; ++i)
    threads.emplace_back([&] {
      Client c(port);
      while (Clock::now() < end)
        if (c.request(http::verb::get, "/api/v1/captures/" + j.id, j.token).first == 200) ++ok;
    });
  for (auto& t : threads) t.join();
  return double(ok) / seconds;
}

void write_outputs(const Args& a, const std::vector<Job>& jobs, nlohmann::json summary) {
  std::vector<std::vector<std::string>> rows;
  lorgnette::ChartSeries wait{"queue wait", {}, {}}, cap{"capture", {}, {}}, train{"train", {}, {}},
      fit{"fit", {}, {}}, total{"total", {}, {}};
  for (size_t i = 0; i < jobs.size(); ++i) {
    const Job& j = jobs[i];
    auto st = [&](const char* s) { return j.stage_s.count(s) ? j.stage_s.at(s) : 0.0; };
    auto cpu = [&](const char* s) { return j.cpu_s.count(s) ? j.cpu_s.at(s) : 0.0; };
    rows.push_back({std::to_string(i + 1), j.id, j.state, std::to_string(j.attempts),
                    fmt::format("{:.2f}", j.upload_s), fmt::format("{:.2f}", j.queue_wait_s),
                    fmt::format("{:.2f}", st("capture")), fmt::format("{:.2f}", st("train")),
                    fmt::format("{:.2f}", st("fit")), fmt::format("{:.2f}", j.fit_only_s),
                    fmt::format("{:.2f}", j.tryon_s), fmt::format("{:.2f}", j.total_s),
                    fmt::format("{:.2f}", cpu("capture")), fmt::format("{:.2f}", cpu("train")),
                    fmt::format("{:.2f}", cpu("fit"))});
    const double x = double(i + 1);
    for (auto [series, v] : std::vector<std::pair<lorgnette::ChartSeries*, double>>{{&wait, j.queue_wait_s},
                                                                                    {&cap, st("capture")},
                                                                                    {&train, st("train")},
                                                                                    {&fit, st("fit")},
                                                                                    {&total, j.total_s}})
      series->x.push_back(x), series->y.push_back(v);
  }
  lorgnette::write_csv(
      a.out + "/jobs.csv",
      {"shopper", "id", "state", "attempts", "upload_s", "queue_wait_s", "capture_s", "train_s", "fit_s",
       "fit_placement_s", "fit_tryon_pictures_s", "total_s", "capture_cpu_s", "train_cpu_s", "fit_cpu_s"},
      rows);
  lorgnette::write_chart(
      a.out + "/jobs.png",
      {fmt::format("{} shoppers, {} worker slot(s): seconds per job", jobs.size(), a.workers),
       "shopper (in the order the queue served them)", "seconds"},
      {wait, cap, train, fit, total});
  std::ofstream(a.out + "/summary.json") << summary.dump(2) << "\n";
}

std::string admin_metrics(uint16_t port) {
  return Client(port).request(http::verb::get, "/metrics", kAdmin).second;
}

// The value of the Prometheus sample `name` (with its labels) in `metrics`, -1 when absent.
double metric(const std::string& metrics, const std::string& name) {
  std::istringstream in(metrics);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(name + " ", 0) == 0) return std::stod(line.substr(name.size() + 1));
  return -1.0;
}

double mtime_s(const fs::path& p) {
  return std::chrono::duration<double>(fs::last_write_time(p).time_since_epoch()).count();
}

// Lines of the server's log saying a worker of job `id` ended: one per worker start.
int worker_ends(const std::string& log, const std::string& id) {
  int n = 0;
  for (size_t at = 0; (at = log.find("job " + id + ": worker ended", at)) != std::string::npos; ++at) ++n;
  return n;
}

// What the folder of one finished job holds: its progress says finished, its dataset and model are
// there, and each catalogue frame has its placement and try-on pictures. Fills the fit / try-on split.
bool folder_complete(const fs::path& dir, int frames, Job& j) {
  const auto progress = nlohmann::json::parse(read_text(dir / "progress.json"), nullptr, false);
  if (progress.is_discarded() || progress.value("state", "") != "finished") return false;
  if (!fs::exists(dir / "dataset/transforms.json") || !fs::exists(dir / "model/head.lnerf")) return false;
  int fitted = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir / "fits", ec)) {
    if (!fs::exists(e.path() / "placement.json") || !fs::exists(e.path() / "views.json")) continue;
    ++fitted;
    if (fitted == 1) {
      j.fit_only_s = mtime_s(e.path() / "placement.json") - mtime_s(dir / "model/head.lnerf");
      j.tryon_s = mtime_s(e.path() / "views.json") - mtime_s(e.path() / "placement.json");
    }
  }
  return fitted == frames;
}

// Counts from the store (the server's /metrics, read before anything else is created) and from the
// data folder, independent of what the shoppers saw: N finished rows and nothing else, N capture
// folders each complete, and one worker start per job in the server's log.
nlohmann::json check_store_and_folders(const Args& a, const std::string& metrics, std::vector<Job>& jobs) {
  nlohmann::json c;
  for (const char* s : {"created", "queued", "running", "failed", "finished"})
    c["store"][s] = metric(metrics, fmt::format("lorgnette_jobs{{state=\"{}\"}}", s));
  const std::string log = read_text(fs::path(a.out) / "server" / "serve.log");
  int folders = 0, complete = 0, one_worker = 0;
  std::set<std::string> known;
  for (Job& j : jobs) known.insert(j.id);
  folders = int(std::distance(fs::directory_iterator(fs::path(a.out) / "data" / "captures"), {}));
  for (Job& j : jobs) {
    if (j.id.empty()) continue;
    complete += folder_complete(fs::path(a.out) / "data" / "captures" / j.id, a.frames, j);
    one_worker += worker_ends(log, j.id) == 1;
  }
  c["folders"] = folders, c["folders_complete"] = complete, c["one_worker_end_in_server_log"] = one_worker;
  const double n = a.shoppers;
  c["ok"] = c["store"]["finished"] == n && c["store"]["failed"] == 0 && c["store"]["queued"] == 0 &&
            c["store"]["running"] == 0 && c["store"]["created"] == 0 && folders == a.shoppers &&
            complete == a.shoppers && one_worker == a.shoppers && int(known.size()) == a.shoppers;
  return c;
}

}  // namespace

namespace {

// Starts `serve` on an ephemeral port over OUT/data; returns the process and its port.
std::pair<std::unique_ptr<ChildProcess>, uint16_t> start_server(const Args& a) {
  const fs::path data = fs::path(a.out) / "data", state = fs::path(a.out) / "server";
  fs::remove_all(data);
  fs::create_directories(state);
  fs::remove(state / "port");
  std::ofstream(state / "admin-token") << kAdmin << "\n";
  std::vector<std::string> argv{a.lorgnette,
                                "serve",
                                "--data",
                                data.string(),
                                "--port",
                                "0",
                                "--port-file",
                                (state / "port").string(),
                                "--admin-token-file",
                                (state / "admin-token").string(),
                                "--workers",
                                std::to_string(a.workers),
                                "--train-steps",
                                std::to_string(a.train_steps),
                                "--train-batch-log2",
                                std::to_string(a.train_batch_log2)};
  // 0: the service's own default for the capture's sampling.
  if (a.capture_fps > 0) argv.insert(argv.end(), {"--capture-fps", fmt::format("{}", a.capture_fps)});
  if (a.capture_max_side > 0)
    argv.insert(argv.end(), {"--capture-max-side", std::to_string(a.capture_max_side)});
  if (!a.db.empty()) argv.insert(argv.end(), {"--db", a.db});
  if (a.frames > 0) argv.insert(argv.end(), {"--catalogue", make_catalogue(a).string()});
  auto p = std::make_unique<ChildProcess>(argv, (state / "serve.log").string());
  for (int i = 0; i < 600 && !fs::exists(state / "port"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  if (!fs::exists(state / "port"))
    throw std::runtime_error("serve did not start: see " + (state / "serve.log").string());
  return {std::move(p), uint16_t(std::stoi(read_text(state / "port")))};
}

// Peak resident memory of the server and of its workers, sampled every 0.2 s until stopped.
// CPU seconds (user + system, its reaped children such as COLMAP and ffmpeg included) that process
// `pid` has used so far, from /proc/<pid>/stat; -1 when it is gone.
double cpu_seconds(pid_t pid) {
  const std::string stat = read_text(fmt::format("/proc/{}/stat", pid));
  const size_t paren = stat.rfind(')');
  if (paren == std::string::npos) return -1.0;
  std::istringstream in(stat.substr(paren + 2));
  std::string field;
  double ticks = 0;
  for (int i = 3; i <= 17 && in >> field; ++i)  // fields 14-17: utime stime cutime cstime
    if (i >= 14) ticks += std::stod(field);
  return ticks / double(sysconf(_SC_CLK_TCK));
}

// The job a worker runs (the last word of `job run FOLDER`) and the stage its progress.json names.
std::pair<std::string, std::string> worker_job_stage(pid_t pid) {
  const std::string cmd = read_text(fmt::format("/proc/{}/cmdline", pid));
  std::vector<std::string> words;
  for (size_t at = 0; at < cmd.size();) {
    const size_t end = cmd.find('\0', at);
    words.push_back(cmd.substr(at, end - at));
    at = end == std::string::npos ? cmd.size() : end + 1;
  }
  if (words.size() < 3 || words[words.size() - 3] != "job") return {"", ""};
  const fs::path folder = words.back();
  const auto p = nlohmann::json::parse(read_text(folder / "progress.json"), nullptr, false);
  return {folder.filename().string(), p.is_discarded() ? "" : p.value("stage", "")};
}

// Peak memory of the server and its workers, the load average, and each worker's CPU seconds by the
// job and stage it was in, sampled every 0.2 s until stopped.
struct MemoryMonitor {
  pid_t server;
  std::map<pid_t, double> cpu_seen;                                 // per worker, at its last sample
  std::map<std::string, std::map<std::string, double>> cpu_by_job;  // job id -> stage -> CPU seconds
  std::atomic<bool> stop{false};
  double server_peak_kb = 0, worker_peak_kb = 0, workers_total_peak_kb = 0;
  double load_sum = 0, load_max = 0;  // the machine's 1-minute load average, over the samples
  long load_samples = 0;
  std::thread thread;
  explicit MemoryMonitor(pid_t pid) : server(pid) {
    thread = std::thread([this] {
      while (!stop) {
        server_peak_kb = std::max(server_peak_kb, rss_kb(server));
        double total = 0;
        for (pid_t c : children(server)) {
          const double kb = rss_kb(c);
          worker_peak_kb = std::max(worker_peak_kb, kb), total += kb;
          sample_cpu(c);
        }
        workers_total_peak_kb = std::max(workers_total_peak_kb, total);
        double load = 0;
        std::istringstream(read_text("/proc/loadavg")) >> load;
        load_sum += load, load_max = std::max(load_max, load), ++load_samples;
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
      }
    });
  }
  ~MemoryMonitor() { finish(); }
  void finish() {
    stop = true;
    if (thread.joinable()) thread.join();
  }
  void sample_cpu(pid_t c) {
    const double now = cpu_seconds(c);
    const auto [job, stage] = worker_job_stage(c);
    if (now < 0 || job.empty()) return;
    const double before = cpu_seen.count(c) ? cpu_seen[c] : 0.0;
    cpu_by_job[job][stage.empty() ? "start" : stage] += now - before;
    cpu_seen[c] = now;
  }
};

std::vector<Job> run_shoppers(const Args& a, uint16_t port, const std::string& video) {
  std::vector<Job> jobs(a.shoppers);
  std::vector<std::string> errors(a.shoppers);
  std::vector<std::thread> threads;
  for (int i = 0; i < a.shoppers; ++i)
    threads.emplace_back([&, i] {
      try {
        jobs[i] = shopper(port, video, a.timeout_seconds);
      } catch (const std::exception& e) {
        errors[i] = e.what();
      }
    });
  for (auto& t : threads) t.join();
  for (int i = 0; i < a.shoppers; ++i)
    if (!errors[i].empty()) fmt::print(stderr, "shopper {}: {}\n", i + 1, errors[i]);
  return jobs;
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  CLI::App app{"The try-on service under N shoppers on loopback (CSV, chart, summary.json)"};
  app.add_option("--out", a.out, "output folder")->required();
  app.add_option("--shoppers", a.shoppers, "shoppers at once");
  app.add_option("--workers", a.workers, "serve --workers");
  app.add_option("--train-steps", a.train_steps, "the shop-wide training budget (serve --train-steps)");
  app.add_option("--train-batch-log2", a.train_batch_log2,
                 "serve --train-batch-log2 (0: the device's batch)");
  app.add_option("--frames", a.frames,
                 "catalogue frames fitted per job (0: no fit stage; a fit needs a budget that makes a face, "
                 "e.g. --train-steps 0 --train-batch-log2 0, the product's defaults)");
  app.add_option("--views", a.views, "frames of the synthetic head turn");
  app.add_option("--size", a.size, "their size, WxH");
  app.add_option("--samples", a.samples, "synth --samples (anti-aliasing samples per pixel axis)");
  app.add_option("--video-fps", a.video_fps,
                 "synthetic views per second of video (the video is written at 30)");
  app.add_option("--video", a.video, "use this video instead of a synthetic one");
  app.add_option("--capture-fps", a.capture_fps, "serve --capture-fps (0: the service's default)");
  app.add_option("--capture-max-side", a.capture_max_side,
                 "serve --capture-max-side (0: the service's default)");
  app.add_option("--db", a.db, "serve --db (default: SQLite in the data folder)");
  app.add_option("--status-seconds", a.status_seconds, "seconds of the status-endpoint load");
  app.add_option("--status-clients", a.status_clients, "keep-alive clients of the status-endpoint load");
  app.add_option("--idle-captures", a.idle_captures, "captures created to measure memory per open capture");
  app.add_option("--lorgnette", a.lorgnette, "the lorgnette binary");
  app.add_option("--timeout", a.timeout_seconds, "seconds a shopper waits for their job before giving up");
  CLI11_PARSE(app, argc, argv);
  try {
    fs::create_directories(a.out);
    const std::string video = read_text(make_video(a));
    auto [server, port] = start_server(a);
    const double rss0 = rss_kb(server->pid());
    std::vector<Job> jobs;
    const auto t0 = Clock::now();
    double server_peak = 0, worker_peak = 0, workers_total_peak = 0, load_mean = 0, load_max = 0;
    {
      MemoryMonitor mem(server->pid());
      jobs = run_shoppers(a, port, video);
      server_peak = mem.server_peak_kb, worker_peak = mem.worker_peak_kb;
      workers_total_peak = mem.workers_total_peak_kb;
      load_mean = mem.load_samples ? mem.load_sum / mem.load_samples : 0.0, load_max = mem.load_max;
      mem.finish();
      for (Job& j : jobs)
        if (mem.cpu_by_job.count(j.id)) j.cpu_s = mem.cpu_by_job[j.id];
    }
    const double wall = since(t0);
    nlohmann::json check = check_store_and_folders(a, admin_metrics(port), jobs);
    // Rows in the order the queue served the jobs (shortest queue wait first).
    std::sort(jobs.begin(), jobs.end(),
              [](const Job& x, const Job& y) { return x.queue_wait_s < y.queue_wait_s; });
    std::set<std::string> ids;
    int finished = 0, single_start = 0;
    for (const Job& j : jobs) ids.insert(j.id), finished += j.ok, single_start += j.attempts == 1;
    Client admin(port);
    const std::string metrics = admin_metrics(port);
    const double rps = jobs.empty() || jobs[0].id.empty()
                           ? 0
                           : status_rps(port, jobs[0], a.status_clients, a.status_seconds);
    const double rss1 = rss_kb(server->pid());
    for (int i = 0; i < a.idle_captures; ++i) admin.request(http::verb::post, "/api/v1/captures", "", "{}");
    const double rss2 = rss_kb(server->pid());
    server->signal(SIGTERM);
    server->wait();
    double stage_sum = 0;
    nlohmann::json cpu_mean = nlohmann::json::object();
    for (const Job& j : jobs) {
      stage_sum += j.total_s - j.queue_wait_s;
      for (const auto& [stage, sec] : j.cpu_s)
        cpu_mean[stage] = cpu_mean.value(stage, 0.0) + sec / double(jobs.size());
    }
    nlohmann::json summary = {
        {"shoppers", a.shoppers},
        {"workers", a.workers},
        {"train_steps", a.train_steps},
        {"video", a.video.empty()
                      ? nlohmann::json{{"views", a.views}, {"size", a.size}, {"bytes", video.size()}}
                      : nlohmann::json{{"file", a.video}, {"bytes", video.size()}}},
        {"capture_fps", a.capture_fps},
        {"capture_max_side", a.capture_max_side},
        {"frames", a.frames},
        {"finished", finished},
        {"distinct_ids", ids.size()},
        {"one_worker_start_each", single_start},
        {"wall_seconds", wall},
        {"jobs_per_hour", finished / wall * 3600.0},
        {"seconds_per_job_in_a_worker_mean", jobs.empty() ? 0 : stage_sum / jobs.size()},
        {"worker_cpu_seconds_per_job_mean", cpu_mean},
        {"status_requests_per_second", rps},
        {"status_clients", a.status_clients},
        {"server_rss_kb", {{"idle", rss0}, {"peak_under_load", server_peak}, {"after_load", rss1}}},
        {"server_rss_kb_per_open_capture", a.idle_captures > 0 ? (rss2 - rss1) / a.idle_captures : 0.0},
        {"worker_rss_kb_peak", worker_peak},
        {"workers_rss_kb_peak_total", workers_total_peak},
        {"load_average_1min", {{"mean", load_mean}, {"max", load_max}}},
        {"check", check},
        {"server_metrics", metrics}};
    write_outputs(a, jobs, summary);
    fmt::print(
        "{} of {} finished ({} distinct ids, {} with one worker start) in {:.1f} s: {:.1f} jobs/hour\n",
        finished, a.shoppers, ids.size(), single_start, wall, finished / wall * 3600.0);
    fmt::print(
        "status endpoint: {:.0f} requests/s ({} keep-alive clients); server RSS {:.0f} kB idle, {:.0f} kB "
        "peak; {:.2f} kB per open capture; worker peak {:.0f} kB\n",
        rps, a.status_clients, rss0, server_peak, summary["server_rss_kb_per_open_capture"].get<double>(),
        worker_peak);
    fmt::print("store and folders: {}\n", check.dump());
    const bool all_good = finished == a.shoppers && int(ids.size()) == a.shoppers &&
                          single_start == a.shoppers && check["ok"].get<bool>();
    if (!all_good) fmt::print(stderr, "NOT all jobs finished exactly once: see {}/jobs.csv\n", a.out);
    return all_good ? 0 : 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "service_load_bench: {}\n", e.what());
    return 2;
  }
}
