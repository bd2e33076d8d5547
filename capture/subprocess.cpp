// POSIX fork/exec child processes with their output in a log file (see subprocess.h).
#include "capture/subprocess.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "host/util/interrupt.h"

namespace fs = std::filesystem;

namespace lorgnette::capture {

fs::path find_executable(const std::string& name) {
  auto executable = [](const fs::path& p) {
    return fs::is_regular_file(p) && ::access(p.c_str(), X_OK) == 0;
  };
  if (name.find('/') != std::string::npos) return executable(name) ? fs::path(name) : fs::path();
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    if (dir.empty()) continue;
    fs::path candidate = fs::path(dir) / name;
    if (executable(candidate)) return candidate;
  }
  return {};
}

ProcessResult run_process(const fs::path& exe, const std::vector<std::string>& args, const fs::path& log,
                          const std::vector<std::string>& env, const std::function<void()>& poll) {
  int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  if (fd < 0)
    throw std::runtime_error(
        fmt::format("cannot create log file '{}': {}", log.string(), std::strerror(errno)));
  std::vector<std::string> argv_s{exe.string()};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  // The child's environment is built here: between fork and exec only async-signal-safe calls.
  std::vector<std::string> env_s;
  for (char** e = environ; e && *e; ++e) {
    std::string entry(*e);
    std::string key = entry.substr(0, entry.find('='));
    bool overridden = false;
    for (const auto& x : env) overridden |= x.compare(0, key.size() + 1, key + "=") == 0;
    if (!overridden) env_s.push_back(entry);
  }
  env_s.insert(env_s.end(), env.begin(), env.end());
  std::vector<char*> envp;
  for (auto& e : env_s) envp.push_back(e.data());
  envp.push_back(nullptr);
  auto start = std::chrono::steady_clock::now();
  pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fd);
    throw std::runtime_error(
        fmt::format("cannot start '{}': fork failed: {}", exe.string(), std::strerror(errno)));
  }
  if (pid == 0) {  // child: only async-signal-safe calls until exec
    ::dup2(fd, STDOUT_FILENO);
    ::dup2(fd, STDERR_FILENO);
    ::close(fd);
    ::execve(argv[0], argv.data(), envp.data());
    const char msg[] = "lorgnette: exec failed\n";
    [[maybe_unused]] auto n = ::write(STDERR_FILENO, msg, sizeof(msg) - 1);
    ::_exit(127);
  }
  ::close(fd);
  ProcessResult result;
  int status = 0;
  for (;;) {
    pid_t r = ::waitpid(pid, &status, WNOHANG);
    if (r == pid) break;
    if (r < 0 && errno != EINTR) break;
    if (interrupted() && !result.interrupted) {
      result.interrupted = true;
      ::kill(pid, SIGTERM);
    }
    if (poll) poll();
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return result;
}

std::string file_tail(const fs::path& path, size_t max_lines) {
  std::ifstream f(path);
  if (!f) return "";
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(f, line)) {
    lines.push_back(line);
    if (lines.size() > 4 * max_lines + 64) lines.erase(lines.begin(), lines.end() - max_lines);
  }
  size_t first = lines.size() > max_lines ? lines.size() - max_lines : 0;
  std::string out;
  for (size_t i = first; i < lines.size(); ++i) out += "  | " + lines[i] + "\n";
  return out;
}

}  // namespace lorgnette::capture
