// The HTTP transport of `lorgnette serve` (Boost.Beast, as the viewer): a listener and one thread
// per connection (at most max_connections at once; more are answered 503), each reading a request
// header, handing it to the Api with a BodySource that streams the body only when asked (uploads go
// to disk in chunks, never whole into memory), and writing the response. Headers are limited to
// 8 KB; a connection silent for `idle_seconds` is closed. Binds to 127.0.0.1 unless told otherwise.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

#include "service/api.h"

namespace lorgnette::service {

struct HttpOptions {
  std::string host = "127.0.0.1";
  uint16_t port = 8080;  // 0: any free port (tests)
  int max_connections = 64;
  int idle_seconds = 30;
};

bool is_loopback(const std::string& host);

class HttpServer {
 public:
  HttpServer(Api& api, const HttpOptions& options);  // binds and listens; throws with the reason
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  uint16_t port() const;
  void start();  // accepts on a background thread
  void stop();   // closes the listener; open connections end after their current request

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  std::thread thread_;
};

}  // namespace lorgnette::service
