// A child process started with fork + execv (no shell, so no argument is ever interpreted), its
// output appended to a log file, and its end as the executor needs it: an exit status, or the
// signal that killed it. The child gets SIGKILL when the thread that started it ends (Linux
// PR_SET_PDEATHSIG), so start children from a long-lived thread. Owning: the destructor of a still-running
// child kills and reaps it, so no worker outlives the object that started it by accident.
#pragma once
#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

namespace lorgnette::service {

struct ChildEnd {
  bool exited = false;  // true: `code` is the exit status; false: killed by `signal`
  int code = 0;
  int signal = 0;
};

class ChildProcess {
 public:
  // Starts argv[0] (a path) with argv; stdout and stderr go to `log_path` (appended; "" = inherited).
  // Throws when the process cannot be started.
  ChildProcess(const std::vector<std::string>& argv, const std::string& log_path);
  ~ChildProcess();
  ChildProcess(ChildProcess&& other) noexcept;
  ChildProcess& operator=(ChildProcess&& other) noexcept;
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  // The end, when the child has ended (reaped then); nothing while it runs.
  std::optional<ChildEnd> poll();
  ChildEnd wait();
  void signal(int sig) const;  // no-op once reaped

 private:
  void kill_and_reap();
  pid_t pid_ = -1;
};

// The path of the running executable (/proc/self/exe), for starting `lorgnette job run`.
std::string self_executable();

}  // namespace lorgnette::service
