// The viewer server on 127.0.0.1 with Boost.Beast's own client, on the fixture's tiny head
// (make_fixture.sh): the page and thumbnails over HTTP (and the Host/Origin checks), a first coarse
// then full frame over the WebSocket, a camera change that changes the frame, errors for malformed,
// unknown, oversized and binary messages with the server still serving, the hard size limit closing
// only that connection, two clients with their own cameras, nudge + save (refused without
// confirmation, then replaced with a backup), and a client that disconnects mid-render freeing its
// session. One test fits a frame that has no placement and checks the fit is cached beside it.
// Misbehaving peers (idle WebSockets filling one address's share, a process out of file
// descriptors) leave a real client served, and failed accepts log a bounded number of lines.
#include "viewer/server.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>

#include "viewer/viewer_service.h"

namespace {

using namespace lorgnette;
using namespace lorgnette::viewer;
namespace fs = std::filesystem;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using nlohmann::json;
using namespace std::chrono_literals;

const fs::path kFixture = fs::path(LORGNETTE_TEST_TMP) / "viewer-fixture";

// A copy of the fixture's catalogue per test, so saves and fits do not leak between tests.
fs::path catalogue_copy(const std::string& name) {
  fs::path d = fs::path(LORGNETTE_TEST_TMP) / "viewer-server" / name;
  fs::remove_all(d);
  fs::create_directories(d.parent_path());
  fs::copy(kFixture / "catalogue", d, fs::copy_options::recursive);
  return d;
}

ViewerConfig small_config(const fs::path& catalogue, bool fit = false) {
  ViewerConfig c;
  c.model_path = (kFixture / "head.lnerf").string();
  c.catalogue = catalogue_from_dir(catalogue.string());
  c.width = 192, c.height = 108;  // coarse frames 64x36: fast on 2 cores
  c.band_rows = 36;
  c.fit.enabled = fit;
  c.fit.settings.views = 8;
  return c;
}

struct Message {
  bool binary = false;
  std::string text;
  std::vector<uint8_t> bytes;
  json j() const { return json::parse(text); }
  FrameHeader frame() const { return decode_frame_header(bytes.data(), bytes.size()); }
};

// A WebSocket client whose reads time out (async operations run on its own io_context).
class Client {
 public:
  // `from`: the local address to connect from (127.0.0.0/8 is all loopback: another "machine").
  explicit Client(uint16_t port, const std::string& origin = "", const std::string& from = "") : ws_(ioc_) {
    auto& socket = beast::get_lowest_layer(ws_).socket();
    if (!from.empty()) {
      socket.open(tcp::v4());
      socket.bind(tcp::endpoint(net::ip::make_address(from), 0));
    }
    socket.connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
    ws_.set_option(websocket::stream_base::decorator([origin](websocket::request_type& req) {
      if (!origin.empty()) req.set(http::field::origin, origin);
    }));
    ws_.read_message_max(64 << 20);
    ws_.handshake("127.0.0.1:" + std::to_string(port), "/ws");
  }
  void send(const std::string& text) {
    ws_.text(true);
    ws_.write(net::buffer(text));
  }
  void send_binary(const std::vector<uint8_t>& b) {
    ws_.binary(true);
    ws_.write(net::buffer(b));
  }
  std::optional<Message> read(std::chrono::milliseconds timeout = 20s) {
    beast::flat_buffer buf;
    bool done = false;
    beast::error_code ec;
    ws_.async_read(buf, [&](beast::error_code e, size_t) { ec = e, done = true; });
    ioc_.restart();
    ioc_.run_for(timeout);
    if (!done) {
      beast::get_lowest_layer(ws_).cancel();
      ioc_.restart();
      ioc_.run();
      return std::nullopt;
    }
    if (ec) {
      closed_ = true;
      return std::nullopt;
    }
    Message m;
    m.binary = ws_.got_binary();
    if (m.binary) {
      auto d = buf.data();
      m.bytes.assign(static_cast<const uint8_t*>(d.data()), static_cast<const uint8_t*>(d.data()) + d.size());
    } else {
      m.text = beast::buffers_to_string(buf.data());
    }
    return m;
  }
  // Reads until a text message of `type` (frames and other messages are skipped).
  std::optional<json> wait_text(const std::string& type, std::chrono::milliseconds timeout = 20s) {
    auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
      auto m =
          read(std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now()));
      if (!m) return std::nullopt;
      if (!m->binary && m->j()["type"] == type) return m->j();
    }
    return std::nullopt;
  }
  // Reads until a frame of `kind` (and, when given, answering camera `seq`).
  std::optional<Message> wait_frame(FrameKind kind, std::optional<uint32_t> seq = {},
                                    std::chrono::milliseconds timeout = 30s) {
    auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
      auto m =
          read(std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now()));
      if (!m) return std::nullopt;
      if (m->binary && m->frame().kind == kind && (!seq || m->frame().seq == *seq)) return m;
    }
    return std::nullopt;
  }
  bool closed() const { return closed_; }
  void drop() { beast::get_lowest_layer(ws_).socket().close(); }

 private:
  net::io_context ioc_;
  websocket::stream<beast::tcp_stream> ws_;
  bool closed_ = false;
};

// GET over plain HTTP with a chosen Host header; returns status and body.
std::pair<int, std::string> http_get(uint16_t port, const std::string& target, const std::string& host) {
  net::io_context ioc;
  beast::tcp_stream s(ioc);
  s.connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
  http::request<http::empty_body> req{http::verb::get, target, 11};
  req.set(http::field::host, host);
  http::write(s, req);
  beast::flat_buffer b;
  http::response<http::string_body> res;
  http::read(s, b, res);
  return {res.result_int(), res.body()};
}

class ViewerServer : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(kFixture / ".complete"))
      GTEST_SKIP() << "the viewer fixture is missing: run ctest -R viewer_fixture";
  }
  void start(ViewerConfig config, ServerOptions o = {}) {
    service_ = std::make_unique<ViewerService>(std::move(config));
    o.port = 0;
    server_ = std::make_unique<Server>(*service_, o);
    server_->start();
  }
  void TearDown() override {
    server_.reset();
    service_.reset();
  }
  uint16_t port() const { return server_->port(); }
  std::unique_ptr<ViewerService> service_;
  std::unique_ptr<Server> server_;
};

TEST_F(ViewerServer, ServesThePageAndThumbnailsOnlyToLoopbackHosts) {
  start(small_config(catalogue_copy("http")));
  std::string host = "127.0.0.1:" + std::to_string(port());
  auto [status, body] = http_get(port(), "/", host);
  EXPECT_EQ(status, 200);
  EXPECT_NE(body.find("viewer.js"), std::string::npos);
  EXPECT_EQ(http_get(port(), "/viewer.js", "localhost:" + std::to_string(port())).first, 200);
  auto thumb = http_get(port(), "/thumb/1.jpg", host);
  EXPECT_EQ(thumb.first, 200);
  ASSERT_GT(thumb.second.size(), 3u);
  EXPECT_EQ(uint8_t(thumb.second[0]), 0xff);  // JPEG SOI
  EXPECT_EQ(http_get(port(), "/thumb/2.jpg", host).first, 404);
  EXPECT_EQ(http_get(port(), "/thumb/-1.jpg", host).first, 404);
  EXPECT_EQ(http_get(port(), "/../../etc/passwd", host).first, 404);
  EXPECT_EQ(http_get(port(), "/", "attacker.example:80").first, 403);            // DNS rebinding
  EXPECT_THROW(Client(port(), "http://attacker.example"), beast::system_error);  // cross-origin WebSocket
}

TEST_F(ViewerServer, FirstFrameIsCoarseThenFullAndACameraChangeChangesIt) {
  start(small_config(catalogue_copy("frames")));
  Client c(port());
  auto info = c.wait_text("info");
  ASSERT_TRUE(info);
  EXPECT_EQ((*info)["catalogue"].size(), 2u);
  EXPECT_NE((*info)["limits"]["source"].get<std::string>().find("capture"), std::string::npos);
  auto coarse = c.wait_frame(FrameKind::kCoarseJpeg);
  ASSERT_TRUE(coarse) << "no coarse frame";
  EXPECT_EQ(coarse->frame().width, 64);
  auto full = c.wait_frame(FrameKind::kFullJpeg);
  ASSERT_TRUE(full) << "no full frame";
  EXPECT_EQ(full->frame().width, 192);
  EXPECT_EQ(full->frame().height, 108);
  EXPECT_EQ(full->bytes[FrameHeader::kSize], 0xff);  // JPEG
  c.send(R"({"type":"camera","yaw":25,"pitch":5,"seq":7})");
  auto moved = c.wait_frame(FrameKind::kFullJpeg, 7u);
  ASSERT_TRUE(moved);
  EXPECT_NE(moved->bytes, full->bytes);
  // Glasses off changes the frame again (before/after).
  c.send(R"({"type":"glasses","on":false})");
  auto state = c.wait_text("state");
  ASSERT_TRUE(state);
  EXPECT_FALSE((*state)["glasses_on"].get<bool>());
  auto off = c.wait_frame(FrameKind::kFullJpeg, 7u);
  ASSERT_TRUE(off);
  EXPECT_NE(off->bytes, moved->bytes);
}

TEST_F(ViewerServer, BadMessagesGetErrorsAndTheServerKeepsServing) {
  start(small_config(catalogue_copy("errors")));
  Client c(port());
  ASSERT_TRUE(c.wait_text("info"));
  const std::pair<std::string, std::string> cases[] = {
      {"{not json", "malformed"},
      {R"({"type":"teleport"})", "unknown_type"},
      {R"({"type":"camera","yaw":"left","pitch":0})", "invalid"},
      {R"({"type":"select","index":99})", "invalid"},
      {R"({"type":"ping","pad":")" + std::string(8000, 'x') + "\"}", "too_large"},
  };
  for (const auto& [text, code] : cases) {
    c.send(text);
    auto e = c.wait_text("error");
    ASSERT_TRUE(e) << "no error for " << text.substr(0, 40);
    EXPECT_EQ((*e)["code"], code) << text.substr(0, 40);
  }
  c.send_binary({1, 2, 3});
  auto e = c.wait_text("error");
  ASSERT_TRUE(e);
  EXPECT_EQ((*e)["code"], "binary");
  c.send(R"({"type":"ping","seq":5})");
  auto pong = c.wait_text("pong");
  ASSERT_TRUE(pong) << "the server stopped answering after bad messages";
  EXPECT_EQ((*pong)["seq"], 5);
  EXPECT_GE(service_->stats().errors_sent, 6u);

  // Beyond the hard limit the server closes that connection only.
  Client big(port());
  ASSERT_TRUE(big.wait_text("info"));
  big.send(std::string(kHardMessageBytes + 10, ' '));
  for (int i = 0; i < 50 && !big.closed(); ++i) big.read(200ms);
  EXPECT_TRUE(big.closed());
  c.send(R"({"type":"ping","seq":6})");
  EXPECT_TRUE(c.wait_text("pong"));
}

TEST_F(ViewerServer, TwoClientsHaveTheirOwnCameras) {
  start(small_config(catalogue_copy("two")));
  Client a(port()), b(port());
  a.send(R"({"type":"camera","yaw":20,"pitch":0,"seq":1})");
  b.send(R"({"type":"camera","yaw":-20,"pitch":0,"seq":1})");
  auto fa = a.wait_frame(FrameKind::kFullJpeg, 1u);
  auto fb = b.wait_frame(FrameKind::kFullJpeg, 1u);
  ASSERT_TRUE(fa && fb);
  EXPECT_NE(fa->bytes, fb->bytes);
  EXPECT_EQ(service_->stats().clients, 2u);
}

TEST_F(ViewerServer, NudgeAndSaveNeedConfirmationToReplaceAndKeepABackup) {
  fs::path cat = catalogue_copy("save");
  start(small_config(cat));
  Client c(port());
  ASSERT_TRUE(c.wait_text("state"));
  std::string placement = (cat / "a-round.glb.placement.json").string();
  fit::PlacementFile before = fit::read_placement(placement);
  c.send(R"({"type":"nudge","up_mm":1.0})");
  auto state = c.wait_text("state");
  ASSERT_TRUE(state);
  EXPECT_DOUBLE_EQ((*state)["nudge"]["up_mm"].get<double>(), 1.0);
  c.send(R"({"type":"save"})");
  auto refused = c.wait_text("error");
  ASSERT_TRUE(refused);
  EXPECT_EQ((*refused)["code"], "exists");
  c.send(R"({"type":"save","overwrite":true})");
  auto saved = c.wait_text("saved");
  ASSERT_TRUE(saved);
  ASSERT_TRUE(saved->contains("backup"));
  EXPECT_TRUE(fs::exists(cat / (*saved)["backup"].get<std::string>()));
  fit::PlacementFile after = fit::read_placement(placement);
  Eigen::Vector3d moved = after.transform.block<3, 1>(0, 3) - before.transform.block<3, 1>(0, 3);
  Eigen::Vector3d up = before.transform.block<3, 1>(0, 1);  // 1 mm along the frame's up, in scene units
  EXPECT_NEAR((moved - up).norm(), 0.0, 1e-9 + 1e-6 * up.norm());
  // The second frame has no placement file; with fitting off it gets a rough stand-in.
  c.send(R"({"type":"select","index":1})");
  auto s1 = c.wait_text("state");
  ASSERT_TRUE(s1);
  EXPECT_EQ((*s1)["frame"]["index"], 1);
  EXPECT_NE((*s1)["frame"]["source"].get<std::string>().find("rough"), std::string::npos);
}

TEST_F(ViewerServer, SnapshotsArePngAtFullSize) {
  start(small_config(catalogue_copy("snapshot")));
  Client c(port());
  c.send(R"({"type":"snapshot"})");
  auto snap = c.wait_frame(FrameKind::kSnapshotPng);
  ASSERT_TRUE(snap);
  EXPECT_EQ(snap->frame().width, 192);
  EXPECT_EQ(snap->bytes[FrameHeader::kSize + 1], 'P');  // \x89PNG
}

TEST_F(ViewerServer, ADisconnectMidRenderFreesTheSession) {
  ViewerConfig config = small_config(catalogue_copy("disconnect"));
  config.band_rows = 8;  // many bands: the drop lands mid-frame
  start(std::move(config));
  {
    Client c(port());
    c.send(R"({"type":"size","width":960,"height":540})");
    ASSERT_TRUE(c.wait_frame(FrameKind::kCoarseJpeg));
    auto t0 = std::chrono::steady_clock::now();
    while (service_->stats().bands == 0 && std::chrono::steady_clock::now() - t0 < 20s)
      std::this_thread::sleep_for(10ms);
    EXPECT_GT(service_->stats().bands, 0u) << "refinement never started";
    c.drop();
  }
  auto t0 = std::chrono::steady_clock::now();
  while (service_->stats().clients > 0 && std::chrono::steady_clock::now() - t0 < 10s)
    std::this_thread::sleep_for(20ms);
  EXPECT_EQ(service_->stats().clients, 0u) << "the dropped client's session is still held";
  uint64_t bands = service_->stats().bands;
  std::this_thread::sleep_for(500ms);
  EXPECT_LE(service_->stats().bands, bands + 1) << "still rendering for a client that left";
  Client again(port());
  EXPECT_TRUE(again.wait_frame(FrameKind::kFullJpeg));
}

TEST_F(ViewerServer, AFrameWithoutPlacementIsFittedWithProgressAndCached) {
  fs::path cat = catalogue_copy("fit");
  start(small_config(cat, /*fit=*/true));
  Client c(port());
  c.send(R"({"type":"select","index":1})");
  auto started = c.wait_text("fit");
  ASSERT_TRUE(started);
  EXPECT_EQ((*started)["state"], "started");
  bool progress = false;
  std::set<std::string> stages;  // the fit's stages, as the progress messages named them
  std::optional<json> end;
  auto t0 = std::chrono::steady_clock::now();
  while (!end && std::chrono::steady_clock::now() - t0 < 180s) {
    auto m = c.wait_text("fit", 180s);
    ASSERT_TRUE(m);
    if ((*m)["state"] == "progress") {
      progress = true;
      stages.insert((*m)["stage"].get<std::string>());
      EXPECT_FALSE((*m)["stage_label"].get<std::string>().empty());
    }
    if ((*m)["state"] == "done" || (*m)["state"] == "failed") end = m;
  }
  ASSERT_TRUE(end);
  EXPECT_TRUE(progress) << "no progress message during the fit";
  // Every stage start sends a message, so the long ones cannot be missed.
  for (const char* s : {"front", "render_detect", "triangulate", "place"}) EXPECT_TRUE(stages.count(s)) << s;
  EXPECT_EQ((*end)["state"], "done") << (*end).dump();
  EXPECT_TRUE(fs::exists(cat / "b-rect.glb.placement.json"));
  auto state = c.wait_text("state");
  ASSERT_TRUE(state);
  EXPECT_EQ((*state)["frame"]["source"], "fit");
  EXPECT_GT((*state)["frame"]["pd_mm"].get<double>(), 0.0);
  // The panel's scale and fit advice (#44): the placement's, rule by rule.
  const nlohmann::json& f = (*state)["frame"];
  EXPECT_TRUE(f["scale_source"] == "iris" || f["scale_source"] == "mean-face") << f.dump();
  EXPECT_GT(f["pd_uncertainty_mm"].get<double>(), 0.0);
  ASSERT_EQ(f["advice"].size(), 4u) << f.dump();
  EXPECT_EQ(f["advice"][0]["name"], "frame_width");
  EXPECT_FALSE(f["advice"][0]["text"].get<std::string>().empty());
}

// True when the server closes `fd` (end of stream or reset) within `within`.
bool closed_by_server(int fd, std::chrono::milliseconds within) {
  auto end = std::chrono::steady_clock::now() + within;
  while (std::chrono::steady_clock::now() < end) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 50) == 1) {
      char c;
      ssize_t n = ::recv(fd, &c, 1, MSG_DONTWAIT);
      if (n <= 0) return true;
    }
  }
  return false;
}

TEST_F(ViewerServer, ARealClientIsServedWhileAnotherAddressHoldsIdleConnections) {
  ServerOptions o;
  o.max_clients = 4;
  o.max_per_address = 3;
  o.idle_timeout = 1500ms;
  start(small_config(catalogue_copy("idle")), o);
  // 127.0.0.2 opens WebSockets and never reads (no pong): three fit its share, the fourth is refused.
  std::vector<std::unique_ptr<Client>> idle;
  for (int k = 0; k < 3; ++k) idle.push_back(std::make_unique<Client>(port(), "", "127.0.0.2"));
  bool fourth_refused = false;
  try {
    Client fourth(port(), "", "127.0.0.2");
  } catch (const beast::system_error&) {
    fourth_refused = true;
  }
  EXPECT_TRUE(fourth_refused) << "one address took more than max_per_address connections";
  {
    Client real(port());
    EXPECT_TRUE(real.wait_frame(FrameKind::kFullJpeg)) << "the real client was not served";
  }
  // Unanswered pings close the idle WebSockets within the idle timeout (plus scheduling slack).
  auto t0 = std::chrono::steady_clock::now();
  while (service_->stats().clients > 0 && std::chrono::steady_clock::now() - t0 < 6s)
    std::this_thread::sleep_for(50ms);
  EXPECT_EQ(service_->stats().clients, 0u) << "idle WebSockets were kept open";
  // A plain connection that never sends a request is closed after the idle timeout too.
  net::io_context ioc;
  tcp::socket silent(ioc);
  silent.connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port()));
  EXPECT_FALSE(closed_by_server(silent.native_handle(), 500ms)) << "closed before the idle timeout";
  EXPECT_TRUE(closed_by_server(silent.native_handle(), 4000ms)) << "an idle HTTP connection was kept open";
  // The address got its slots back.
  Client again(port(), "", "127.0.0.2");
  EXPECT_TRUE(again.wait_text("info"));
}

TEST_F(ViewerServer, AcceptFailuresBackOffAndLogOncePerInterval) {
  // The sink is added before the server's threads start and removed after they end (a logger's sink
  // list is not synchronised).
  std::ostringstream log;
  spdlog::default_logger()->sinks().push_back(std::make_shared<spdlog::sinks::ostream_sink_mt>(log));
  ServerOptions o;
  o.log_interval = 10s;
  start(small_config(catalogue_copy("accept")), o);
  // Out of file descriptors: a lower soft limit, filled up, then three peers connect (the kernel
  // queues them; every accept fails with EMFILE until descriptors are free again).
  rlimit old{};
  ASSERT_EQ(getrlimit(RLIMIT_NOFILE, &old), 0);
  int highest = 0;
  for (const auto& e : fs::directory_iterator("/proc/self/fd"))
    highest = std::max(highest, std::atoi(e.path().filename().c_str()));
  rlimit low = old;
  low.rlim_cur = std::min<rlim_t>(old.rlim_cur, rlim_t(highest) + 64);
  ASSERT_EQ(setrlimit(RLIMIT_NOFILE, &low), 0);
  std::vector<int> peers, filler;
  for (int k = 0; k < 3; ++k) peers.push_back(::socket(AF_INET, SOCK_STREAM, 0));
  for (int fd; (fd = ::open("/dev/null", O_RDONLY)) >= 0;) filler.push_back(fd);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(port());
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  for (int fd : peers) EXPECT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&to), sizeof to), 0);
  rusage r0{}, r1{};
  getrusage(RUSAGE_SELF, &r0);
  std::this_thread::sleep_for(1500ms);
  getrusage(RUSAGE_SELF, &r1);
  for (int fd : filler) ::close(fd);
  setrlimit(RLIMIT_NOFILE, &old);
  auto cpu = [](const rusage& r) {
    return double(r.ru_utime.tv_sec + r.ru_stime.tv_sec) +
           1e-6 * double(r.ru_utime.tv_usec + r.ru_stime.tv_usec);
  };
  const double cpu_s = cpu(r1) - cpu(r0);
  // Idle waiting costs next to nothing; spinning on the queued peers costs the whole 1.5 s.
  EXPECT_LT(cpu_s, 0.5) << "the accept loop spun";
  for (int fd : peers) ::close(fd);
  {
    Client real(port());  // descriptors back: the server serves again
    EXPECT_TRUE(real.wait_text("info"));
  }
  server_.reset();
  service_.reset();
  spdlog::default_logger()->sinks().pop_back();
  const std::string text = log.str();
  size_t lines = 0;
  for (size_t at = 0; (at = text.find("accept failed", at)) != std::string::npos; ++at) ++lines;
  // All within one log_interval: one message, however many accepts failed.
  EXPECT_EQ(lines, 1u) << text.substr(0, 2000);
}

}  // namespace
