// Beast listener and connections for the service (http_server.h).
#include "service/http_server.h"

#include <spdlog/spdlog.h>
#include <sys/socket.h>
#include <sys/time.h>

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <condition_variable>
#include <limits>
#include <optional>
#include <set>

namespace beast = boost::beast;
namespace http = beast::http;
namespace net = boost::asio;
using tcp = net::ip::tcp;

namespace lorgnette::service {

bool is_loopback(const std::string& host) {
  return host == "127.0.0.1" || host == "::1" || host == "localhost" || host.rfind("127.", 0) == 0;
}

namespace {

constexpr uint32_t kMaxHeaderBytes = 8 * 1024;

// The body of the request whose header `parser` has read, read on demand.
class BeastBody final : public BodySource {
 public:
  BeastBody(tcp::socket& s, beast::flat_buffer& b, http::request_parser<http::empty_body>& p)
      : socket_(s), buffer_(b), header_(p) {}

  std::string read_all(uint64_t limit) override {
    http::request_parser<http::string_body> p{std::move(header_)};
    p.body_limit(limit);
    read(p);
    return std::move(p.get().body());
  }

  uint64_t read_to_file(const std::filesystem::path& path, uint64_t limit) override {
    http::request_parser<http::file_body> p{std::move(header_)};
    p.body_limit(limit);
    beast::error_code ec;
    p.get().body().open(path.c_str(), beast::file_mode::write_new, ec);
    if (disk_full(ec)) throw InsufficientStorage(ec.message());
    if (ec) throw std::runtime_error("cannot write the upload: " + ec.message());
    read(p);
    p.get().body().file().close(ec);
    return std::filesystem::file_size(path);  // file_body's size() is the size at open
  }

  bool consumed() const { return consumed_; }

 private:
  static bool disk_full(const beast::error_code& ec) {
    return ec == std::errc::no_space_on_device || ec == std::errc::file_too_large ||
           ec == std::error_code(EDQUOT, std::system_category());
  }
  // consumed_ is set only when the whole body was read: after a refusal or an error mid-body the
  // rest of it is still on the wire, so the connection must close rather than read it as a request.
  template <class Parser>
  void read(Parser& p) {
    beast::error_code ec;
    // A client that asked "Expect: 100-continue" (curl does for uploads) waits for this first.
    if (beast::iequals(p.get()[http::field::expect], "100-continue")) {
      http::response<http::empty_body> go{http::status::continue_, 11};
      http::write(socket_, go, ec);
    }
    http::read(socket_, buffer_, p, ec);
    if (ec == http::error::body_limit) throw BodyTooLarge("body over the limit");
    if (disk_full(ec)) throw InsufficientStorage(ec.message());
    if (ec) throw std::runtime_error("the request body could not be read: " + ec.message());
    consumed_ = true;
  }
  tcp::socket& socket_;
  beast::flat_buffer& buffer_;
  http::request_parser<http::empty_body>& header_;
  bool consumed_ = false;
};

void set_timeout(tcp::socket& s, int seconds) {
  timeval tv{seconds, 0};
  ::setsockopt(s.native_handle(), SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  ::setsockopt(s.native_handle(), SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
}

}  // namespace

struct HttpServer::Impl {
  Api& api;
  HttpOptions options;
  net::io_context ioc{1};
  tcp::acceptor acceptor{ioc};
  std::atomic<bool> stopping{false};
  std::mutex mutex;
  std::condition_variable idle;
  int connections = 0;
  std::set<int> sockets;  // open connections' descriptors, shut for reading by stop()

  Impl(Api& a, const HttpOptions& o) : api(a), options(o) {}
  void serve(tcp::socket socket);
  bool serve_one(tcp::socket& socket, beast::flat_buffer& buffer);
};

bool HttpServer::Impl::serve_one(tcp::socket& socket, beast::flat_buffer& buffer) {
  http::request_parser<http::empty_body> header;
  header.header_limit(kMaxHeaderBytes);
  // No body limit while reading the header (Beast's default, 1 MB, would refuse a larger
  // Content-Length before the API sees it); the API sets each body's own limit when it reads it.
  header.body_limit(std::numeric_limits<std::uint64_t>::max());
  beast::error_code ec;
  http::read_header(socket, buffer, header, ec);
  if (ec) return false;  // closed, timed out or not HTTP: nothing to answer
  const auto& req = header.get();
  ApiRequest rq;
  rq.method = std::string(req.method_string());
  rq.target = std::string(req.target());
  rq.authorization = std::string(req[http::field::authorization]);
  if (header.content_length()) rq.content_length = *header.content_length();
  BeastBody body(socket, buffer, header);
  ApiResponse r = api.handle(rq, body);
  // A body the API did not read (an early refusal) is not skipped over: the connection closes.
  const bool has_body = header.content_length().value_or(0) > 0 || header.chunked();
  const bool keep = req.keep_alive() && (body.consumed() || !has_body) && !stopping;
  http::response<http::string_body> res{static_cast<http::status>(r.status), req.version()};
  res.set(http::field::server, "lorgnette");
  res.set(http::field::content_type, r.content_type);
  res.set(http::field::cache_control, "no-store");
  res.body() = std::move(r.body);
  res.keep_alive(keep);
  res.prepare_payload();
  http::write(socket, res, ec);
  return keep && !ec;
}

void HttpServer::Impl::serve(tcp::socket socket) {
  set_timeout(socket, options.idle_seconds);
  beast::flat_buffer buffer;
  try {
    while (serve_one(socket, buffer)) {
    }
  } catch (const std::exception& e) {
    spdlog::warn("connection: {}", e.what());
  }
  // A refused request's unread body: read and drop what the client still sends (for a second at
  // most), so that closing does not reset the connection before the client has read the answer.
  beast::error_code ec;
  socket.shutdown(tcp::socket::shutdown_send, ec);
  set_timeout(socket, 1);
  char sink[16384];
  for (size_t drained = 0; drained < (size_t(64) << 20);) {
    const size_t n = socket.read_some(net::buffer(sink), ec);
    if (ec) break;
    drained += n;
  }
  std::lock_guard<std::mutex> lock(mutex);
  sockets.erase(socket.native_handle());
  --connections;
  idle.notify_all();
}

HttpServer::HttpServer(Api& api, const HttpOptions& options) : impl_(std::make_unique<Impl>(api, options)) {
  auto& a = impl_->acceptor;
  const tcp::endpoint ep{net::ip::make_address(options.host), options.port};
  a.open(ep.protocol());
  a.set_option(net::socket_base::reuse_address(true));
  a.bind(ep);
  a.listen(net::socket_base::max_listen_connections);
  if (!is_loopback(options.host))
    spdlog::warn(
        "serving on {}, not loopback: put it behind a TLS reverse proxy (docs/service.md), since capture "
        "tokens and shoppers' videos would otherwise cross the network in clear text",
        options.host);
}

HttpServer::~HttpServer() { stop(); }

uint16_t HttpServer::port() const { return impl_->acceptor.local_endpoint().port(); }

void HttpServer::start() {
  thread_ = std::thread([this] {
    Impl& s = *impl_;
    while (!s.stopping) {
      beast::error_code ec;
      tcp::socket socket{s.ioc};
      s.acceptor.accept(socket, ec);
      if (ec) continue;
      std::unique_lock<std::mutex> lock(s.mutex);
      if (s.connections >= s.options.max_connections) {
        lock.unlock();
        http::response<http::string_body> busy{http::status::service_unavailable, 11};
        busy.body() =
            "{\"error\": {\"code\": \"busy\", \"message\": \"too many connections; retry shortly\"}}\n";
        busy.prepare_payload();
        http::write(socket, busy, ec);
        continue;
      }
      ++s.connections;
      s.sockets.insert(socket.native_handle());
      lock.unlock();
      std::thread([&s, sock = std::move(socket)]() mutable { s.serve(std::move(sock)); }).detach();
    }
  });
}

void HttpServer::stop() {
  if (!impl_ || impl_->stopping.exchange(true)) return;
  beast::error_code ec;
  impl_->acceptor.cancel(ec);
  ::shutdown(impl_->acceptor.native_handle(), SHUT_RDWR);  // wakes the blocking accept
  impl_->acceptor.close(ec);
  if (thread_.joinable()) thread_.join();
  std::unique_lock<std::mutex> lock(impl_->mutex);
  for (int fd : impl_->sockets) ::shutdown(fd, SHUT_RD);  // idle keep-alive reads end now
  impl_->idle.wait(lock, [&] { return impl_->connections == 0; });
}

}  // namespace lorgnette::service
