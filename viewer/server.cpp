// Boost.Beast HTTP + WebSocket server of the viewer (server.h).
#include "viewer/server.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <deque>
#include <mutex>
#include <optional>

#include "viewer/connection_limits.h"
#include "viewer/web_assets.h"

namespace lorgnette::viewer {
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

// Lets the render and fit threads post to the I/O thread only while it exists. Outside the
// anonymous namespace because Server::Impl, which has external linkage, holds one.
struct IoGate {
  std::mutex m;
  net::io_context* ioc = nullptr;
  template <class F>
  void post(F&& f) {
    std::lock_guard<std::mutex> lock(m);
    if (ioc) net::post(*ioc, std::forward<F>(f));
  }
};

namespace {

// "127.0.0.1:8080" / "[::1]:8080" / "localhost" -> the host name part.
std::string host_name(beast::string_view host_header) {
  std::string h(host_header.data(), host_header.size());
  if (!h.empty() && h[0] == '[')
    return h.substr(1, h.find(']') == std::string::npos ? std::string::npos : h.find(']') - 1);
  return h.substr(0, h.find(':'));
}

}  // namespace

bool is_loopback_host(const std::string& host) {
  if (host == "localhost" || host == "::1" || host == "ip6-localhost") return true;
  boost::system::error_code ec;
  auto a = net::ip::make_address(host, ec);
  return !ec && a.is_loopback();
}

struct Server::Impl {
  ViewerService& service;
  ServerOptions options;
  // Declared before the io_context: connections its destructor closes still count down here.
  std::atomic<size_t> sockets{0};
  AddressLimit per_address{options.max_per_address};
  net::io_context ioc{1};
  tcp::acceptor acceptor{ioc};
  net::steady_timer retry{ioc};
  std::shared_ptr<IoGate> gate = std::make_shared<IoGate>();
  bool loopback = true;
  Backoff accept_backoff{std::chrono::milliseconds(10), std::chrono::milliseconds(1000)};
  ThrottledLog accept_log{options.log_interval}, refuse_log{options.log_interval};

  Impl(ViewerService& s, const ServerOptions& o) : service(s), options(o) {}
  void accept();
  void on_accept(beast::error_code ec, tcp::socket socket);
  void accept_failed(const beast::error_code& ec);
  // The request may reach the page: Host is this machine's loopback name when bound to loopback.
  bool host_allowed(const http::request<http::string_body>& req) const {
    if (!loopback) return true;
    auto it = req.find(http::field::host);
    return it != req.end() && is_loopback_host(host_name(it->value()));
  }
};

namespace {

class WsSession : public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(tcp::socket&& socket, Server::Impl& srv, AddressLimit::Slot slot)
      : ws_(std::move(socket)), srv_(srv), slot_(std::move(slot)) {
    srv_.sockets++;
  }
  ~WsSession() {
    if (id_) srv_.service.disconnect(id_);
    srv_.sockets--;
  }

  void run(http::request<http::string_body> req) {
    websocket::stream_base::timeout timeout;
    timeout.handshake_timeout = std::chrono::seconds(30);
    timeout.idle_timeout = srv_.options.idle_timeout;
    timeout.keep_alive_pings = true;
    ws_.set_option(timeout);
    ws_.read_message_max(kHardMessageBytes);
    ws_.auto_fragment(false);
    ws_.set_option(websocket::stream_base::decorator(
        [](websocket::response_type& res) { res.set(http::field::server, "lorgnette-view"); }));
    ws_.async_accept(req, beast::bind_front_handler(&WsSession::on_accept, shared_from_this()));
  }

  void queue_text(std::string text) {
    if (closed_) return;
    if (texts_.size() >= srv_.options.max_queued_texts) {
      spdlog::warn("view: client {} does not read its replies: disconnecting it", id_);
      return close();
    }
    texts_.push_back(std::move(text));
    write_next();
  }
  void queue_frame(FrameKind kind, std::vector<uint8_t> bytes) {
    if (closed_) return;
    // Latest wins: a newer frame replaces the one not yet sent (snapshots have their own slot).
    (kind == FrameKind::kSnapshotPng ? pending_snapshot_ : pending_view_) = std::move(bytes);
    write_next();
  }

 private:
  // The sink the service holds: it posts to the I/O thread and never keeps the session alive.
  class Outbox : public ClientSink {
   public:
    Outbox(std::shared_ptr<IoGate> gate, std::weak_ptr<WsSession> s)
        : gate_(std::move(gate)), s_(std::move(s)) {}
    void send_text(std::string text) override {
      gate_->post([s = s_, t = std::move(text)]() mutable {
        if (auto p = s.lock()) p->queue_text(std::move(t));
      });
    }
    void send_frame(FrameKind kind, std::vector<uint8_t> bytes) override {
      gate_->post([s = s_, kind, b = std::move(bytes)]() mutable {
        if (auto p = s.lock()) p->queue_frame(kind, std::move(b));
      });
    }

   private:
    std::shared_ptr<IoGate> gate_;
    std::weak_ptr<WsSession> s_;
  };

  void on_accept(beast::error_code ec) {
    if (ec) return;
    id_ = srv_.service.connect(std::make_shared<Outbox>(srv_.gate, weak_from_this()));
    read();
  }
  void read() { ws_.async_read(buffer_, beast::bind_front_handler(&WsSession::on_read, shared_from_this())); }
  void on_read(beast::error_code ec, size_t bytes) {
    if (ec) {
      if (ec == websocket::error::message_too_big)
        spdlog::warn("view: client {} sent a message over {} bytes: disconnected", id_, kHardMessageBytes);
      closed_ = true;
      return;  // the session ends when its last handler returns
    }
    if (ws_.got_text())
      srv_.service.handle_text(id_, beast::buffers_to_string(buffer_.data()));
    else
      srv_.service.handle_binary(id_, bytes);
    buffer_.consume(buffer_.size());
    read();
  }
  void write_next() {
    if (writing_ || closed_) return;
    if (!texts_.empty()) {
      out_text_ = std::move(texts_.front());
      texts_.pop_front();
      ws_.text(true);
      writing_ = true;
      ws_.async_write(net::buffer(out_text_),
                      beast::bind_front_handler(&WsSession::on_write, shared_from_this()));
      return;
    }
    auto& slot = pending_snapshot_ ? pending_snapshot_ : pending_view_;
    if (!slot) return;
    out_bytes_ = std::move(*slot);
    slot.reset();
    ws_.binary(true);
    writing_ = true;
    ws_.async_write(net::buffer(out_bytes_),
                    beast::bind_front_handler(&WsSession::on_write, shared_from_this()));
  }
  void on_write(beast::error_code ec, size_t) {
    writing_ = false;
    out_bytes_ = {};
    if (ec) {
      closed_ = true;
      return;
    }
    write_next();
  }
  void close() {
    closed_ = true;
    texts_.clear();
    pending_view_.reset(), pending_snapshot_.reset();
    beast::error_code ec;
    beast::get_lowest_layer(ws_).socket().shutdown(tcp::socket::shutdown_both, ec);
    beast::get_lowest_layer(ws_).socket().close(ec);
  }

  websocket::stream<beast::tcp_stream> ws_;
  Server::Impl& srv_;
  AddressLimit::Slot slot_;
  beast::flat_buffer buffer_;
  ViewerService::ClientId id_ = 0;
  std::deque<std::string> texts_;
  std::optional<std::vector<uint8_t>> pending_view_, pending_snapshot_;
  std::string out_text_;
  std::vector<uint8_t> out_bytes_;
  bool writing_ = false, closed_ = false;
};

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket&& socket, Server::Impl& srv, AddressLimit::Slot slot)
      : stream_(std::move(socket)), srv_(srv), slot_(std::move(slot)) {}
  void run() { read(); }

 private:
  using Response = http::response<http::string_body>;

  void read() {
    parser_.emplace();
    parser_->header_limit(8192);
    parser_->body_limit(1024);
    stream_.expires_after(srv_.options.idle_timeout);
    http::async_read(stream_, buffer_, *parser_,
                     beast::bind_front_handler(&HttpSession::on_read, shared_from_this()));
  }

  void on_read(beast::error_code ec, size_t) {
    if (ec) {
      beast::error_code ignored;
      stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
      return;
    }
    http::request<http::string_body> req = parser_->release();
    if (websocket::is_upgrade(req)) return upgrade(std::move(req));
    send(respond(req));
  }

  void upgrade(http::request<http::string_body> req) {
    std::string why;
    if (req.target() != "/ws")
      why = "404 the WebSocket is at /ws";
    else if (!srv_.host_allowed(req))
      why = "403 Host is not this machine";
    else if (auto o = req.find(http::field::origin);
             o != req.end() && std::string(o->value()) != "http://" + std::string(req[http::field::host]))
      why = "403 cross-origin WebSocket refused";
    else if (srv_.sockets.load() >= srv_.options.max_clients)
      why = "503 too many viewers connected";
    if (!why.empty()) {
      int status = std::stoi(why.substr(0, 3));
      return send(text_response(req, http::status(status), why.substr(4)));
    }
    stream_.expires_never();
    std::make_shared<WsSession>(stream_.release_socket(), srv_, std::move(slot_))->run(std::move(req));
  }

  Response text_response(const http::request<http::string_body>& req, http::status status,
                         const std::string& text) {
    Response res{status, req.version()};
    res.set(http::field::server, "lorgnette-view");
    res.set(http::field::content_type, "text/plain; charset=utf-8");
    res.keep_alive(req.keep_alive());
    res.body() = text + "\n";
    res.prepare_payload();
    return res;
  }

  Response respond(const http::request<http::string_body>& req) {
    if (req.method() != http::verb::get && req.method() != http::verb::head)
      return text_response(req, http::status::method_not_allowed, "only GET and HEAD");
    if (!srv_.host_allowed(req))
      return text_response(req, http::status::forbidden, "Host is not this machine");
    std::string target(req.target());
    target = target.substr(0, target.find('?'));
    if (target == "/") target = "/index.html";
    Response res{http::status::ok, req.version()};
    res.set(http::field::server, "lorgnette-view");
    res.set(http::field::cache_control, "no-store");
    res.set("X-Content-Type-Options", "nosniff");
    const auto& assets = web_assets();
    if (auto it = assets.find(target); it != assets.end()) {
      res.set(http::field::content_type, it->second.content_type);
      res.set("Content-Security-Policy",
              "default-src 'self'; img-src 'self' blob: data:; connect-src 'self' ws: wss:; frame-ancestors "
              "'none'");
      res.body() = it->second.body;
    } else if (target.rfind("/thumb/", 0) == 0 && target.size() > 11 &&
               target.substr(target.size() - 4) == ".jpg") {
      std::string num = target.substr(7, target.size() - 11);
      const auto& a = srv_.service.assets();
      if (num.empty() || num.size() > 6 || num.find_first_not_of("0123456789") != std::string::npos ||
          std::stoul(num) >= a.size())
        return text_response(req, http::status::not_found, "no such thumbnail");
      const auto& jpg = a.thumbnail_jpeg(std::stoul(num));
      res.set(http::field::content_type, "image/jpeg");
      res.body().assign(jpg.begin(), jpg.end());
    } else {
      return text_response(req, http::status::not_found, "not found");
    }
    res.keep_alive(req.keep_alive());
    res.prepare_payload();
    if (req.method() == http::verb::head) res.body().clear();
    return res;
  }

  void send(Response res) {
    auto sp = std::make_shared<Response>(std::move(res));
    http::async_write(stream_, *sp, [self = shared_from_this(), sp](beast::error_code ec, size_t) {
      if (ec) return;
      if (sp->need_eof()) {
        beast::error_code ignored;
        self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
        return;
      }
      self->read();
    });
  }

  beast::tcp_stream stream_;
  Server::Impl& srv_;
  AddressLimit::Slot slot_;
  beast::flat_buffer buffer_{8192};
  std::optional<http::request_parser<http::string_body>> parser_;
};

}  // namespace

void Server::Impl::accept() {
  acceptor.async_accept(
      ioc, [this](beast::error_code ec, tcp::socket socket) { on_accept(ec, std::move(socket)); });
}

void Server::Impl::on_accept(beast::error_code ec, tcp::socket socket) {
  if (ec == net::error::operation_aborted || !acceptor.is_open()) return;
  if (ec) return accept_failed(ec);
  accept_backoff.reset();
  beast::error_code peer_ec;
  std::string peer = socket.remote_endpoint(peer_ec).address().to_string();
  AddressLimit::Slot slot = per_address.acquire(peer_ec ? std::string("?") : peer);
  if (slot) {
    std::make_shared<HttpSession>(std::move(socket), *this, std::move(slot))->run();
  } else {
    if (auto held = refuse_log.admit())
      spdlog::warn(
          "view: refused a connection from {}: it already holds {} ({} more refused since the last "
          "message)",
          peer, options.max_per_address, *held);
    socket.close(peer_ec);
  }
  accept();
}

// The failed connection stays queued (EMFILE, ENFILE, ENOBUFS): wait before taking it again.
void Server::Impl::accept_failed(const beast::error_code& ec) {
  auto pause = accept_backoff.next();
  if (auto held = accept_log.admit())
    spdlog::warn("view: accept failed: {} ({} more failures since the last message); retrying in {} ms",
                 ec.message(), *held, pause.count());
  retry.expires_after(pause);
  retry.async_wait([this](beast::error_code wait_ec) {
    if (!wait_ec) accept();
  });
}

Server::Server(ViewerService& service, const ServerOptions& options)
    : impl_(std::make_unique<Impl>(service, options)) {
  boost::system::error_code ec;
  auto address = net::ip::make_address(options.host == "localhost" ? "127.0.0.1" : options.host, ec);
  if (ec)
    throw std::runtime_error(
        fmt::format("--host '{}' is not an IP address ({})", options.host, ec.message()));
  impl_->loopback = address.is_loopback();
  tcp::endpoint ep(address, options.port);
  auto& a = impl_->acceptor;
  a.open(ep.protocol(), ec);
  if (!ec) a.set_option(net::socket_base::reuse_address(true), ec);
  if (!ec) a.bind(ep, ec);
  if (!ec) a.listen(net::socket_base::max_listen_connections, ec);
  if (ec)
    throw std::runtime_error(fmt::format("cannot listen on {}:{}: {} (try another --port)", options.host,
                                         options.port, ec.message()));
  impl_->gate->ioc = &impl_->ioc;
  impl_->accept();
}

Server::~Server() {
  stop();
  // Destroying the io_context destroys the pending handlers, hence the sessions (they disconnect
  // from the service) while the context still exists.
  impl_.reset();
}

uint16_t Server::port() const { return impl_->acceptor.local_endpoint().port(); }

std::string Server::url() const {
  auto ep = impl_->acceptor.local_endpoint();
  std::string host = ep.address().is_v6() ? "[" + ep.address().to_string() + "]" : ep.address().to_string();
  return fmt::format("http://{}:{}/", host, ep.port());
}

void Server::run() { impl_->ioc.run(); }

void Server::start() {
  thread_ = std::thread([this] { impl_->ioc.run(); });
}

void Server::stop() {
  if (!impl_) return;
  {
    std::lock_guard<std::mutex> lock(impl_->gate->m);
    impl_->gate->ioc = nullptr;
  }
  impl_->ioc.stop();
  if (thread_.joinable() && thread_.get_id() != std::this_thread::get_id()) thread_.join();
}

}  // namespace lorgnette::viewer
