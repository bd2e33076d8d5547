// Runs an external program (COLMAP) as a child process with its standard output and error captured
// in a log file, polling so the caller can show progress from the log and stop the child on Ctrl-C.
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace lorgnette::capture {

// Absolute path of `name` found on PATH (or `name` itself when it contains a '/' and is
// executable); empty when not found.
std::filesystem::path find_executable(const std::string& name);

struct ProcessResult {
  int exit_code = 0;  // exit status; 128 + signal number when killed by a signal
  bool interrupted = false;
  double seconds = 0;
};

// Runs `exe args...` with stdout+stderr appended to `log` and `env` ("NAME=value") added to the
// environment. `poll` is called about 5 times a second while it runs. Ctrl-C (host/util/interrupt)
// terminates the child. Throws only when the log cannot be created or fork fails.
ProcessResult run_process(const std::filesystem::path& exe, const std::vector<std::string>& args,
                          const std::filesystem::path& log, const std::vector<std::string>& env,
                          const std::function<void()>& poll);

// The last `max_lines` lines of a text file ("" when it cannot be read).
std::string file_tail(const std::filesystem::path& path, size_t max_lines);

}  // namespace lorgnette::capture
