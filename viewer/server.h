// The viewer's HTTP + WebSocket server (Boost.Beast) over a ViewerService. HTTP serves the embedded
// page (/, /viewer.js, /viewer.css) and the catalogue's thumbnails (/thumb/N.jpg); GET /ws upgrades
// to the viewer protocol (protocol.h). One I/O thread runs every connection; rendering happens on the
// service's render thread, which hands frames back through each connection's bounded outbox.
//
// Safe by default: it binds to 127.0.0.1 unless told otherwise; on a loopback address it answers only
// requests whose Host is a loopback name (no DNS rebinding) and WebSocket upgrades whose Origin, when
// present, is this server; HTTP requests are GET/HEAD with at most 8 KB of headers; a client that
// stops reading its replies (a full outbox) is disconnected; at most `max_clients` at once.
//
// One peer cannot take the viewer from the others: each remote address holds at most
// `max_per_address` connections (HTTP and WebSocket together; more are closed at once), a connection
// that sends no request (HTTP) or answers no ping (WebSocket) within `idle_timeout` is closed, and a
// failed accept (out of file descriptors) is retried after a pause that grows to a second, logged
// at most once per `log_interval` instead of spinning.
#pragma once
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

#include "viewer/viewer_service.h"

namespace lorgnette::viewer {

struct ServerOptions {
  std::string host = "127.0.0.1";
  uint16_t port = 8080;  // 0: any free port (tests)
  size_t max_clients = 64;
  size_t max_queued_texts = 256;  // per connection, before it counts as not reading
  // A browser page opens one WebSocket and up to 6 HTTP connections; a few tabs fit.
  size_t max_per_address = 16;
  // HTTP: the time to send the next request; WebSocket: a ping goes out after half of it without a
  // message and the connection closes when the other half passes without an answer (browsers answer
  // pings on their own, so an open page is never idle).
  std::chrono::milliseconds idle_timeout{30000};
  std::chrono::milliseconds log_interval{10000};  // accept failures and refusals: one message per
};

bool is_loopback_host(const std::string& host);

class Server {
 public:
  // Binds and listens (throws with the reason when the address is taken or invalid).
  Server(ViewerService& service, const ServerOptions& options);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  uint16_t port() const;
  std::string url() const;  // http://host:port/
  void run();               // serves on this thread until stop()
  void start();             // serves on a background thread
  void stop();              // thread-safe; closes the listener and every connection

  struct Impl;  // the connections' shared state (server.cpp)

 private:
  std::unique_ptr<Impl> impl_;
  std::thread thread_;
};

}  // namespace lorgnette::viewer
