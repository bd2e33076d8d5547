// Running the `lorgnette` binary from a test as a user would (shared by the CLI tests in this folder):
// a fresh folder per test, the command's exit status, stderr and time, and a tiny model written
// through the snapshot format (no device needed).
#pragma once
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "host/nerf/snapshot.h"

namespace lgn_cli_test {

struct CliResult {
  int status = -1;
  std::string err;
  double seconds = 0.0;
};

// A fresh folder named after the running test, under LORGNETTE_TEST_TMP/<suite>.
inline std::filesystem::path test_dir(const char* suite) {
  std::filesystem::path d = std::filesystem::path(LORGNETTE_TEST_TMP) / suite /
                            ::testing::UnitTest::GetInstance()->current_test_info()->name();
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Runs `lorgnette -q <args>` in `dir` with a 60 s limit (a hang exits 124).
inline CliResult run_cli(const std::filesystem::path& dir, const std::string& args) {
  const std::filesystem::path err = dir / "stderr.txt";
  std::string cmd = "cd '" + dir.string() + "' && timeout 60 '" LGN_CLI_PATH "' -q " + args +
                    " > /dev/null 2> '" + err.string() + "'";
  auto t0 = std::chrono::steady_clock::now();
  int raw = std::system(cmd.c_str());
  CliResult r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.err = read_file(err);
  return r;
}

inline void write_file(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

// Runs the command once and checks it was refused with `part` on stderr (and no raw bad_alloc).
#define EXPECT_REFUSED(call, part)                                                      \
  do {                                                                                  \
    const CliResult res_ = (call);                                                      \
    EXPECT_EQ(res_.status, 1) << res_.err;                                              \
    EXPECT_NE(res_.err.find(part), std::string::npos) << "stderr: " << res_.err;        \
    EXPECT_EQ(res_.err.find("bad_alloc"), std::string::npos) << "stderr: " << res_.err; \
  } while (0)

// A tiny untrained model: the snapshot format written directly (no device needed here).
inline void write_tiny_model(const std::filesystem::path& path) {
  using namespace lorgnette::nerf;
  Snapshot s;
  s.config.log2_table_size = 10;
  s.config.finest_resolution = 32;
  s.config.levels = 4;
  s.aabb = {{-1, -1, -1}, {1, 1, 1}};
  s.step = 0.02f;
  s.params.assign(s.config.param_count(), 0.0f);
  s.occ = full_occupancy(8);
  std::ofstream(path, std::ios::binary) << encode_snapshot(s);
}

}  // namespace lgn_cli_test
