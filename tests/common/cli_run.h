// The `lorgnette` binary run as a user runs it, for the tests that check what it says and leaves
// behind: one command line in a folder of the test's own (fresh_test_dir), standard output dropped
// or kept in a file, standard error kept for the checks, and the exit status as the shell reports it.
#pragma once
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/common/text_and_errors.h"

namespace lorgnette::testing {

struct CliResult {
  int status = -1;       // exit status (124 when `timeout_s` ran out, as timeout(1) exits)
  std::string err;       // standard error
  double seconds = 0.0;  // wall time of the whole command
};

struct CliCall {
  std::string stdout_to = "/dev/null";  // a file in the folder (relative to it), or /dev/null
  int timeout_s = 0;                    // > 0: the command is stopped after this long
};

// Runs `<cli> <args>` in `dir` through the shell (args as a user types them, quoting included);
// standard error goes to dir/stderr.txt and comes back in the result.
inline CliResult run_cli(const std::string& cli, const std::filesystem::path& dir, const std::string& args,
                         const CliCall& call = {}) {
  const std::filesystem::path err = dir / "stderr.txt";
  const std::string limit = call.timeout_s > 0 ? "timeout " + std::to_string(call.timeout_s) + " " : "";
  const std::string cmd = "cd '" + dir.string() + "' && " + limit + "'" + cli + "' " + args + " > '" +
                          call.stdout_to + "' 2> '" + err.string() + "'";
  const auto t0 = std::chrono::steady_clock::now();
  const int raw = std::system(cmd.c_str());
  CliResult r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.err = read(err);
  return r;
}

// A fresh, empty folder for the running test: <root>/<group>/<test name>.
inline std::filesystem::path fresh_test_dir(const std::filesystem::path& root, const std::string& group) {
  const std::filesystem::path d =
      root / group / ::testing::UnitTest::GetInstance()->current_test_info()->name();
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

inline void write_file(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

}  // namespace lorgnette::testing
