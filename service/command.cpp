// Short commands with captured output (command.h).
#include "service/command.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>

namespace fs = std::filesystem;

namespace lorgnette::service {
namespace {

// Owns both ends of a pipe.
struct Pipe {
  int fd[2] = {-1, -1};
  Pipe() {
    if (::pipe2(fd, O_CLOEXEC) != 0) fd[0] = fd[1] = -1;
  }
  ~Pipe() {
    for (int f : fd)
      if (f >= 0) ::close(f);
  }
  void close_end(int i) {
    if (fd[i] >= 0) ::close(fd[i]);
    fd[i] = -1;
  }
};

// Reads both pipes until they close or the deadline passes; returns false on the deadline.
bool drain(Pipe& out, Pipe& err, CommandResult& r, std::chrono::steady_clock::time_point deadline) {
  char buf[4096];
  while (out.fd[0] >= 0 || err.fd[0] >= 0) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return false;
    pollfd p[2] = {{out.fd[0], POLLIN, 0}, {err.fd[0], POLLIN, 0}};
    if (::poll(p, 2, int(left.count())) < 0 && errno != EINTR) return false;
    for (int i = 0; i < 2; ++i) {
      Pipe& pipe = i == 0 ? out : err;
      if (pipe.fd[0] < 0 || !(p[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      const ssize_t n = ::read(pipe.fd[0], buf, sizeof buf);
      if (n > 0)
        (i == 0 ? r.out : r.err).append(buf, size_t(n));
      else if (n == 0 || errno != EINTR)
        pipe.close_end(0);
    }
  }
  return true;
}

}  // namespace

CommandResult run_command(const std::vector<std::string>& argv, double timeout_seconds) {
  CommandResult r;
  if (argv.empty()) return r.err = "no command", r;
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  Pipe out, err;
  if (out.fd[0] < 0 || err.fd[0] < 0) return r.err = std::string("cannot make a pipe: ") + strerror(errno), r;
  const pid_t pid = ::fork();
  if (pid == 0) {  // child: only async-signal-safe calls until execv
    ::dup2(out.fd[1], 1), ::dup2(err.fd[1], 2);
    const int null_fd = ::open("/dev/null", O_RDONLY);
    if (null_fd >= 0) ::dup2(null_fd, 0);
    if (::close_range(3, ~0U, 0) != 0)
      for (int fd = 3; fd < 65536; ++fd) ::close(fd);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  if (pid < 0) return r.err = std::string("cannot start ") + argv[0] + ": " + strerror(errno), r;
  out.close_end(1), err.close_end(1);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_seconds);
  const bool in_time =
      drain(out, err, r, std::chrono::time_point_cast<std::chrono::steady_clock::duration>(deadline));
  if (!in_time) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!in_time) {
    r.err += "\n" + argv[0] + " did not answer within " + std::to_string(int(timeout_seconds)) + " s";
  } else if (WIFEXITED(status)) {
    r.status = WEXITSTATUS(status);
    if (r.status == 127 && r.out.empty() && r.err.empty()) r.err = "cannot run " + argv[0];
  } else {
    r.err += "\n" + argv[0] + " was killed by signal " + std::to_string(WTERMSIG(status));
  }
  return r;
}

std::string find_program(const std::string& name, const std::string& dir) {
  std::vector<std::string> dirs;
  if (!dir.empty()) {
    dirs.push_back(dir);
  } else if (const char* path = std::getenv("PATH")) {
    std::stringstream ss(path);
    for (std::string d; std::getline(ss, d, ':');)
      if (!d.empty()) dirs.push_back(d);
  }
  for (const auto& d : dirs) {
    const fs::path p = fs::path(d) / name;
    if (::access(p.c_str(), X_OK) == 0 && fs::is_regular_file(p)) return fs::absolute(p).string();
  }
  return "";
}

}  // namespace lorgnette::service
