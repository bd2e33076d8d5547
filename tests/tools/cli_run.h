// The CLI tests of this folder (bounds, sweep): the shared runner (tests/common/cli_run.h) with a
// 60 s limit and `-q`, a refusal check, and a tiny model written through the snapshot format (no
// device needed).
#pragma once
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "host/nerf/snapshot.h"
#include "tests/common/cli_run.h"

namespace lgn_cli_test {

using lorgnette::testing::CliResult;
using lorgnette::testing::write_file;

inline std::string read_file(const std::filesystem::path& p) { return lorgnette::testing::read(p); }

// A fresh folder named after the running test, under LORGNETTE_TEST_TMP/<suite>.
inline std::filesystem::path test_dir(const char* suite) {
  return lorgnette::testing::fresh_test_dir(LORGNETTE_TEST_TMP, suite);
}

// Runs `lorgnette -q <args>` in `dir` with a 60 s limit (a hang exits 124).
inline CliResult run_cli(const std::filesystem::path& dir, const std::string& args) {
  lorgnette::testing::CliCall call;
  call.timeout_s = 60;
  return lorgnette::testing::run_cli(LGN_CLI_PATH, dir, "-q " + args, call);
}

// Runs the command once and checks it was refused with `part` on stderr (and no raw bad_alloc).
#define EXPECT_REFUSED(call, part)                                                      \
  do {                                                                                  \
    const CliResult res_ = (call);                                                      \
    EXPECT_EQ(res_.status, 1) << res_.err;                                              \
    EXPECT_NE(res_.err.find(part), std::string::npos) << "stderr: " << res_.err;        \
    EXPECT_EQ(res_.err.find("bad_alloc"), std::string::npos) << "stderr: " << res_.err; \
  } while (0)

// A tiny untrained model: the snapshot format written directly.
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
