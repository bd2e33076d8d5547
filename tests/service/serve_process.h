// `lorgnette serve` as a real child process for the service tests: a loopback ephemeral port
// (read from --port-file), an admin token, and its log; restartable on the same folders. Its
// port file, token and log live in `state`, beside (not inside) the data folder, so that the data
// folder can be a small tmpfs or be deleted by the test.
#pragma once
#include <signal.h>

#include <optional>
#include <string>
#include <vector>

#include "service/child_process.h"
#include "service_test_util.h"

namespace lorgnette::service::test {

inline const std::string kTestAdminToken = "admin-0123456789abcdef0123456789abcdef";

class ServeProcess {
 public:
  ServeProcess(fs::path data, fs::path state, std::vector<std::string> extra)
      : data_(std::move(data)), state_(std::move(state)), extra_(std::move(extra)) {
    start();
  }
  void start() {
    fs::create_directories(state_);
    fs::remove(state_ / "port");
    write_file(state_ / "admin-token", kTestAdminToken + "\n");
    std::vector<std::string> argv{LGN_CLI_PATH,
                                  "serve",
                                  "--data",
                                  data_.string(),
                                  "--port",
                                  "0",
                                  "--port-file",
                                  (state_ / "port").string(),
                                  "--admin-token-file",
                                  (state_ / "admin-token").string()};
    argv.insert(argv.end(), extra_.begin(), extra_.end());
    process_.emplace(argv, (state_ / "serve.log").string());
    if (!wait_for([&] { return fs::exists(state_ / "port") || process_->poll(); }, 60.0) ||
        !fs::exists(state_ / "port"))
      throw std::runtime_error("serve did not start: " + log());
    port_ = uint16_t(std::stoi(read_file(state_ / "port")));
  }
  ChildEnd stop(int sig) {
    process_->signal(sig);
    ChildEnd end = process_->wait();
    process_.reset();
    return end;
  }
  uint16_t port() const { return port_; }
  std::string log() const { return read_file(state_ / "serve.log"); }

 private:
  fs::path data_, state_;
  std::vector<std::string> extra_;
  std::optional<ChildProcess> process_;
  uint16_t port_ = 0;
};

}  // namespace lorgnette::service::test
