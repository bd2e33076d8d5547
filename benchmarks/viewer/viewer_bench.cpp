// Viewer benchmarks over real WebSockets on 127.0.0.1 (the server and the Beast clients in one
// process), writing CSV + PNG charts and summary.json into --out:
//  latency.csv/.png  input -> first coarse frame and -> full still, per trial (camera jumps with the
//                    user idle after each; the full still waits for the idle delay, included)
//  drag.csv          a drag at 60 messages/s: frames per second and input -> frame latency (coarse
//                    frames: the viewer's interactive path)
//  stills.csv        full frames back to back (--stills-seconds): a camera move, its full still, the
//                    next move at once; full frames per second (each after its coarse frame, as the
//                    viewer renders every change; with --idle-ms 0 no idle wait is included)
//  summary.csv       one row: viewport, device, coarse and full frames per second, latency medians
//  load.csv/.png     N clients for S seconds, each moving its camera every 250 ms and sending a
//                    malformed message every 5 s: frames served and errors per client
//  summary.json      medians, memory per client (RSS growth / clients, and the stated bound)
// Everything is bounded in time and stops by itself.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>

#include "host/util/chart.h"
#include "viewer/server.h"
#include "viewer/viewer_service.h"

using namespace lorgnette;
using namespace lorgnette::viewer;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using Clock = std::chrono::steady_clock;

namespace {

double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

size_t rss_bytes() {
  std::ifstream in("/proc/self/status");
  std::string key;
  while (in >> key) {
    if (key == "VmRSS:") {
      size_t kb = 0;
      in >> kb;
      return kb * 1024;
    }
    in.ignore(1 << 12, '\n');
  }
  return 0;
}

// An asynchronous client on a shared io_context: reads continuously, writes through a queue.
class BenchClient : public std::enable_shared_from_this<BenchClient> {
 public:
  std::function<void(const FrameHeader&, size_t bytes)> on_frame;
  std::function<void(const nlohmann::json&)> on_text;
  bool failed = false;

  BenchClient(net::io_context& ioc, uint16_t port) : ws_(ioc) {
    beast::get_lowest_layer(ws_).connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
    ws_.read_message_max(64 << 20);
    ws_.handshake("127.0.0.1:" + std::to_string(port), "/ws");
  }
  void start() { read(); }
  void send(std::string text) {
    out_.push_back(std::move(text));
    if (out_.size() == 1) write();
  }
  void close() {
    beast::error_code ec;
    beast::get_lowest_layer(ws_).socket().close(ec);
  }

 private:
  void read() {
    ws_.async_read(buf_, [self = shared_from_this()](beast::error_code ec, size_t) {
      if (ec) {
        self->failed = ec != net::error::operation_aborted && ec != websocket::error::closed &&
                       ec != net::error::bad_descriptor;
        return;
      }
      auto d = self->buf_.data();
      if (self->ws_.got_binary()) {
        FrameHeader h = decode_frame_header(static_cast<const uint8_t*>(d.data()), d.size());
        if (self->on_frame) self->on_frame(h, d.size());
      } else if (self->on_text) {
        self->on_text(nlohmann::json::parse(beast::buffers_to_string(d)));
      }
      self->buf_.consume(self->buf_.size());
      self->read();
    });
  }
  void write() {
    ws_.text(true);
    ws_.async_write(net::buffer(out_.front()), [self = shared_from_this()](beast::error_code ec, size_t) {
      if (ec) {
        self->failed = true;
        return;
      }
      self->out_.pop_front();
      if (!self->out_.empty()) self->write();
    });
  }

  websocket::stream<beast::tcp_stream> ws_;
  beast::flat_buffer buf_;
  std::deque<std::string> out_;
};

std::string camera(double yaw, double pitch, bool interacting, uint32_t seq) {
  return nlohmann::json(
             {{"type", "camera"}, {"yaw", yaw}, {"pitch", pitch}, {"interacting", interacting}, {"seq", seq}})
      .dump();
}

struct Args {
  std::string model, glasses, placement, catalogue, out = "bench-viewer", size = "854x480";
  int trials = 8, drag_seconds = 10, load_clients = 20, load_seconds = 60, stills_seconds = 0, idle_ms = -1;
  uint32_t band_rows = 96, coarse = 3;
  bool skip_load = false;
};

// Latency: per trial a camera jump, then the time to its coarse frame and to its full frame.
std::vector<std::array<double, 2>> bench_latency(net::io_context& ioc, uint16_t port, int trials) {
  auto c = std::make_shared<BenchClient>(ioc, port);
  std::vector<std::array<double, 2>> out;
  uint32_t seq = 0;
  Clock::time_point sent;
  double coarse_ms = -1;
  bool warm = false;
  net::steady_timer timer(ioc);
  std::function<void()> next = [&] {
    if (int(out.size()) >= trials) return ioc.stop();
    ++seq;
    coarse_ms = -1;
    sent = Clock::now();
    c->send(camera(seq % 2 ? 20.0 : -20.0, seq % 3 ? 5.0 : -5.0, false, seq));
  };
  c->on_frame = [&](const FrameHeader& h, size_t) {
    if (!warm) {  // the first full frame: kernels built, caches warm
      if (h.kind == FrameKind::kFullJpeg) warm = true, next();
      return;
    }
    if (h.seq != seq) return;
    if (h.kind == FrameKind::kCoarseJpeg && coarse_ms < 0) coarse_ms = ms_since(sent);
    if (h.kind == FrameKind::kFullJpeg) {
      out.push_back({coarse_ms, ms_since(sent)});
      fmt::print("latency trial {}: coarse {:.0f} ms, full {:.0f} ms\n", out.size(), coarse_ms,
                 out.back()[1]);
      timer.expires_after(std::chrono::milliseconds(300));
      timer.async_wait([&](beast::error_code) { next(); });
    }
  };
  c->start();
  ioc.restart();
  ioc.run_for(std::chrono::seconds(30 + 10 * trials));
  c->close();
  ioc.restart();
  ioc.poll();
  return out;
}

struct DragResult {
  std::vector<double> fps_per_second, latency_ms;
};

// A drag: camera messages at 60 Hz with interacting = true; counts the frames that come back.
DragResult bench_drag(net::io_context& ioc, uint16_t port, int seconds) {
  auto c = std::make_shared<BenchClient>(ioc, port);
  DragResult r;
  std::map<uint32_t, Clock::time_point> sent;
  uint32_t seq = 0;
  int frames_this_second = 0;
  bool warm = false;
  Clock::time_point start;
  net::steady_timer tick(ioc), second(ioc);
  std::function<void()> send_next = [&] {
    ++seq;
    sent[seq] = Clock::now();
    double t = ms_since(start) / 1000.0;
    c->send(camera(25.0 * std::sin(t * 1.5), 8.0 * std::sin(t * 0.7), true, seq));
    tick.expires_after(std::chrono::microseconds(16667));
    tick.async_wait([&](beast::error_code ec) {
      if (!ec) send_next();
    });
  };
  std::function<void()> count = [&] {
    r.fps_per_second.push_back(frames_this_second);
    frames_this_second = 0;
    if (int(r.fps_per_second.size()) >= seconds) return ioc.stop();
    second.expires_after(std::chrono::seconds(1));
    second.async_wait([&](beast::error_code ec) {
      if (!ec) count();
    });
  };
  c->on_frame = [&](const FrameHeader& h, size_t) {
    if (!warm) {
      if (h.kind == FrameKind::kFullJpeg) {
        warm = true;
        start = Clock::now();
        send_next();
        second.expires_after(std::chrono::seconds(1));
        second.async_wait([&](beast::error_code ec) {
          if (!ec) count();
        });
      }
      return;
    }
    frames_this_second++;
    if (auto it = sent.find(h.seq); it != sent.end()) r.latency_ms.push_back(ms_since(it->second));
  };
  c->start();
  ioc.restart();
  ioc.run_for(std::chrono::seconds(seconds + 40));
  tick.cancel(), second.cancel();
  c->close();
  ioc.restart();
  ioc.poll();
  return r;
}

struct StillsResult {
  std::vector<double> full_per_second, coarse_per_second, full_ms;  // full_ms: camera move -> full still
};

// Full stills back to back: each camera move (not interacting) is answered by a coarse frame and,
// after the idle delay, the full still; the next move goes out as soon as the still arrives.
StillsResult bench_stills(net::io_context& ioc, uint16_t port, int seconds) {
  auto c = std::make_shared<BenchClient>(ioc, port);
  StillsResult r;
  uint32_t seq = 0;
  int full = 0, coarse = 0;
  bool warm = false;
  Clock::time_point sent;
  net::steady_timer second(ioc);
  auto next = [&] {
    ++seq;
    sent = Clock::now();
    c->send(camera(seq % 2 ? 15.0 : -15.0, seq % 3 ? 4.0 : -4.0, false, seq));
  };
  std::function<void()> count = [&] {
    r.full_per_second.push_back(full);
    r.coarse_per_second.push_back(coarse);
    full = coarse = 0;
    if (int(r.full_per_second.size()) >= seconds) return ioc.stop();
    second.expires_after(std::chrono::seconds(1));
    second.async_wait([&](beast::error_code ec) {
      if (!ec) count();
    });
  };
  c->on_frame = [&](const FrameHeader& h, size_t) {
    if (!warm) {  // the first full frame: kernels built, caches warm
      if (h.kind != FrameKind::kFullJpeg) return;
      warm = true;
      second.expires_after(std::chrono::seconds(1));
      second.async_wait([&](beast::error_code ec) {
        if (!ec) count();
      });
      return next();
    }
    if (h.kind == FrameKind::kCoarseJpeg) ++coarse;
    if (h.kind != FrameKind::kFullJpeg || h.seq != seq) return;
    ++full;
    r.full_ms.push_back(ms_since(sent));
    next();
  };
  c->start();
  ioc.restart();
  ioc.run_for(std::chrono::seconds(seconds + 40));
  second.cancel();
  c->close();
  ioc.restart();
  ioc.poll();
  return r;
}

struct LoadStats {
  uint64_t coarse = 0, full = 0, protocol_errors = 0, unexpected_errors = 0;
  bool failed = false;
};

// N clients, each moving its camera every 250 ms (drag bursts, then still) and sending a malformed
// message every 5 s (answered with an error: counted, expected); unexpected errors and failed
// connections are counted separately.
std::vector<LoadStats> bench_load(net::io_context& ioc, uint16_t port, int clients, int seconds,
                                  size_t& rss_peak) {
  std::vector<std::shared_ptr<BenchClient>> cs;
  std::vector<LoadStats> stats(clients);
  std::vector<std::unique_ptr<net::steady_timer>> timers;
  std::vector<uint32_t> seqs(clients, 0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> yaw(-30, 30), pitch(-10, 10);
  std::vector<std::function<void()>> tick(clients);
  for (int i = 0; i < clients; ++i) {
    cs.push_back(std::make_shared<BenchClient>(ioc, port));
    cs[i]->on_frame = [&, i](const FrameHeader& h, size_t) {
      (h.kind == FrameKind::kFullJpeg ? stats[i].full : stats[i].coarse)++;
    };
    cs[i]->on_text = [&, i](const nlohmann::json& j) {
      if (j["type"] != "error") return;
      (j["code"] == "malformed" ? stats[i].protocol_errors : stats[i].unexpected_errors)++;
    };
    timers.push_back(std::make_unique<net::steady_timer>(ioc));
    tick[i] = [&, i] {
      uint32_t s = ++seqs[i];
      // 8 ticks moving (2 s of interaction), 4 still (1 s to refine)
      bool moving = s % 12 < 8;
      if (moving || s % 12 == 8) cs[i]->send(camera(yaw(rng), pitch(rng), moving, s));
      if (s % 20 == 0) cs[i]->send("{malformed");
      timers[i]->expires_after(std::chrono::milliseconds(250));
      timers[i]->async_wait([&, i](beast::error_code ec) {
        if (!ec) tick[i]();
      });
    };
    cs[i]->start();
    tick[i]();
  }
  net::steady_timer sampler(ioc);
  std::function<void()> sample = [&] {
    rss_peak = std::max(rss_peak, rss_bytes());
    sampler.expires_after(std::chrono::milliseconds(500));
    sampler.async_wait([&](beast::error_code ec) {
      if (!ec) sample();
    });
  };
  sample();
  ioc.restart();
  ioc.run_for(std::chrono::seconds(seconds));
  for (auto& t : timers) t->cancel();
  sampler.cancel();
  for (int i = 0; i < clients; ++i) {
    stats[i].failed = cs[i]->failed;
    cs[i]->close();
  }
  ioc.restart();
  ioc.poll();
  return stats;
}

void run(const Args& a) {
  namespace fs = std::filesystem;
  fs::create_directories(a.out);
  ViewerConfig config;
  config.model_path = a.model;
  config.catalogue =
      a.catalogue.empty() ? catalogue_single(a.glasses, a.placement) : catalogue_from_dir(a.catalogue);
  if (std::sscanf(a.size.c_str(), "%ux%u", &config.width, &config.height) != 2)
    throw std::runtime_error("--size WxH");
  config.fit.enabled = false;
  config.band_rows = a.band_rows;
  config.coarse_divisor = a.coarse;
  if (a.idle_ms >= 0) config.idle_ms = a.idle_ms;
  ViewerService service(config);
  ServerOptions so;
  so.port = 0;
  // Every load client comes from 127.0.0.1, as if one machine ran them all.
  so.max_per_address = std::max<size_t>(so.max_per_address, size_t(a.load_clients) + 4);
  Server server(service, so);
  server.start();
  net::io_context ioc;
  nlohmann::json summary = {{"device", service.device_name()},
                            {"size", a.size},
                            {"model", a.model},
                            {"client_bytes_bound", service.client_bytes_bound()},
                            {"band_rows", a.band_rows},
                            {"coarse_divisor", a.coarse},
                            {"idle_ms", config.idle_ms}};

  auto lat = bench_latency(ioc, server.port(), a.trials);
  std::vector<std::vector<std::string>> rows;
  ChartSeries coarse{"input -> coarse frame", {}, {}}, full{"input -> full still", {}, {}};
  for (size_t i = 0; i < lat.size(); ++i) {
    rows.push_back(
        {std::to_string(i + 1), fmt::format("{:.1f}", lat[i][0]), fmt::format("{:.1f}", lat[i][1])});
    coarse.x.push_back(double(i + 1)), coarse.y.push_back(lat[i][0]);
    full.x.push_back(double(i + 1)), full.y.push_back(lat[i][1]);
  }
  write_csv(a.out + "/latency.csv", {"trial", "coarse_ms", "full_ms"}, rows);
  write_chart(a.out + "/latency.png",
              {"Viewer latency, " + a.size + " (" + service.device_name() + ")", "trial", "ms"},
              {coarse, full});
  summary["latency_coarse_ms_median"] = median(coarse.y);
  summary["latency_full_ms_median"] = median(full.y);

  DragResult drag = bench_drag(ioc, server.port(), a.drag_seconds);
  rows.clear();
  for (size_t i = 0; i < drag.fps_per_second.size(); ++i)
    rows.push_back({std::to_string(i + 1), fmt::format("{}", drag.fps_per_second[i])});
  write_csv(a.out + "/drag.csv", {"second", "frames"}, rows);
  summary["drag_fps_median"] = median(drag.fps_per_second);
  summary["drag_latency_ms_median"] = median(drag.latency_ms);
  fmt::print("drag: {:.1f} fps (median over {} s), input -> frame {:.0f} ms\n", median(drag.fps_per_second),
             drag.fps_per_second.size(), median(drag.latency_ms));

  if (a.stills_seconds > 0) {
    StillsResult st = bench_stills(ioc, server.port(), a.stills_seconds);
    rows.clear();
    for (size_t i = 0; i < st.full_per_second.size(); ++i)
      rows.push_back({std::to_string(i + 1), fmt::format("{}", st.full_per_second[i]),
                      fmt::format("{}", st.coarse_per_second[i])});
    write_csv(a.out + "/stills.csv", {"second", "full_frames", "coarse_frames"}, rows);
    summary["stills_full_fps_median"] = median(st.full_per_second);
    summary["stills_full_ms_median"] = median(st.full_ms);
    fmt::print("stills: {:.1f} full frames per second (median over {} s), move -> full {:.0f} ms\n",
               median(st.full_per_second), st.full_per_second.size(), median(st.full_ms));
  }
  write_csv(a.out + "/summary.csv",
            {"size", "device", "idle_ms", "coarse_fps_drag", "full_fps_stills", "full_ms_stills",
             "latency_coarse_ms", "latency_full_ms", "drag_latency_ms"},
            {{a.size, service.device_name(), std::to_string(config.idle_ms),
              fmt::format("{:.1f}", summary["drag_fps_median"].get<double>()),
              summary.contains("stills_full_fps_median")
                  ? fmt::format("{:.1f}", summary["stills_full_fps_median"].get<double>())
                  : "",
              summary.contains("stills_full_ms_median")
                  ? fmt::format("{:.1f}", summary["stills_full_ms_median"].get<double>())
                  : "",
              fmt::format("{:.1f}", summary["latency_coarse_ms_median"].get<double>()),
              fmt::format("{:.1f}", summary["latency_full_ms_median"].get<double>()),
              fmt::format("{:.1f}", summary["drag_latency_ms_median"].get<double>())}});

  if (!a.skip_load) {
    // Memory per client: RSS with one client idle vs the peak with N active (server and clients
    // share the process; the clients' own buffers are small).
    size_t rss0 = rss_bytes(), peak = rss0;
    auto load = bench_load(ioc, server.port(), a.load_clients, a.load_seconds, peak);
    rows.clear();
    ChartSeries fc{"coarse frames", {}, {}}, ff{"full frames", {}, {}};
    uint64_t frames = 0, expected = 0, unexpected = 0, failed = 0;
    for (size_t i = 0; i < load.size(); ++i) {
      const auto& s = load[i];
      rows.push_back({std::to_string(i), std::to_string(s.coarse), std::to_string(s.full),
                      std::to_string(s.protocol_errors), std::to_string(s.unexpected_errors),
                      s.failed ? "1" : "0"});
      fc.x.push_back(double(i)), fc.y.push_back(double(s.coarse));
      ff.x.push_back(double(i)), ff.y.push_back(double(s.full));
      frames += s.coarse + s.full, expected += s.protocol_errors, unexpected += s.unexpected_errors,
          failed += s.failed;
    }
    fc.points_only = ff.points_only = true;
    write_csv(a.out + "/load.csv",
              {"client", "coarse", "full", "malformed_replies", "unexpected_errors", "failed"}, rows);
    write_chart(a.out + "/load.png",
                {fmt::format("{} clients for {} s: frames per client", a.load_clients, a.load_seconds),
                 "client", "frames"},
                {fc, ff});
    summary["load"] = {{"clients", a.load_clients},
                       {"seconds", a.load_seconds},
                       {"frames", frames},
                       {"frames_per_second", double(frames) / a.load_seconds},
                       {"malformed_replies", expected},
                       {"unexpected_errors", unexpected},
                       {"failed_connections", failed},
                       {"rss_before_mb", rss0 / 1e6},
                       {"rss_peak_mb", peak / 1e6},
                       {"mb_per_client", (double(peak) - double(rss0)) / 1e6 / a.load_clients}};
    fmt::print(
        "load: {} frames in {} s from {} clients ({:.1f}/s), {} malformed replies, {} unexpected errors, "
        "{} failed connections; RSS {:.0f} -> {:.0f} MB\n",
        frames, a.load_seconds, a.load_clients, double(frames) / a.load_seconds, expected, unexpected, failed,
        rss0 / 1e6, peak / 1e6);
  }
  auto st = service.stats();
  summary["server"] = {{"coarse_frames", st.coarse_frames},
                       {"full_frames", st.full_frames},
                       {"bands", st.bands},
                       {"errors_sent", st.errors_sent},
                       {"messages", st.messages}};
  std::ofstream(a.out + "/summary.json") << summary.dump(2) << "\n";
  std::cout << summary.dump(2) << "\n";
  server.stop();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"viewer benchmarks: latency, drag frame rate, load, memory per client"};
  Args a;
  app.add_option("--model", a.model, "trained model (.lnerf), e.g. demo-output/head.lnerf")->required();
  app.add_option("--glasses", a.glasses, "frame file");
  app.add_option("--placement", a.placement, "its placement.json");
  app.add_option("--catalogue", a.catalogue, "or a catalogue folder");
  app.add_option("--out", a.out, "output folder")->capture_default_str();
  app.add_option("--size", a.size, "viewport")->capture_default_str();
  app.add_option("--trials", a.trials, "latency trials")->capture_default_str();
  app.add_option("--drag-seconds", a.drag_seconds, "drag duration")->capture_default_str();
  app.add_option("--clients", a.load_clients, "load: clients")->capture_default_str();
  app.add_option("--load-seconds", a.load_seconds, "load: duration")->capture_default_str();
  app.add_option("--band-rows", a.band_rows, "rows per refinement band")->capture_default_str();
  app.add_option("--coarse", a.coarse, "coarse frames at 1/N resolution")->capture_default_str();
  app.add_flag("--skip-load", a.skip_load, "latency and drag only");
  app.add_option("--stills-seconds", a.stills_seconds, "full stills back to back for S seconds (0: skip)")
      ->check(CLI::Range(0, 600));
  app.add_option("--idle-ms", a.idle_ms, "idle delay before the full still (default: the viewer's 120)")
      ->check(CLI::Range(0, 10000));
  CLI11_PARSE(app, argc, argv);
  spdlog::set_level(spdlog::level::warn);
  try {
    run(a);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
