// Helpers for the service tests: fresh folders, files, JSON, waiting with a deadline, and the tiny
// synthetic dataset (the procedural head, `lorgnette synth`) every job test trains on.
#pragma once
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>

#include "service/child_process.h"
#include "tests/common/cli_run.h"

namespace lorgnette::service::test {

namespace fs = std::filesystem;

// A fresh, empty folder named after the running test.
inline fs::path test_dir(const std::string& suite) {
  return lorgnette::testing::fresh_test_dir(LORGNETTE_TEST_TMP, suite);
}

inline std::string read_file(const fs::path& p) { return lorgnette::testing::read(p); }

inline void write_file(const fs::path& p, const std::string& bytes) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << bytes;
}

inline nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(read_file(p)); }

// Polls `done` every 50 ms until it holds or `seconds` pass; returns whether it held.
inline bool wait_for(const std::function<bool()>& done, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return done();
}

#ifdef LGN_CLI_PATH
// Runs the CLI to its end; returns its exit status (-signal when killed). Output goes to `log`.
inline int run_cli(const std::vector<std::string>& args, const fs::path& log) {
  std::vector<std::string> argv{LGN_CLI_PATH};
  argv.insert(argv.end(), args.begin(), args.end());
  ChildEnd e = ChildProcess(argv, log.string()).wait();
  return e.exited ? e.code : -e.signal;
}

// The procedural head at 64x64 from 8 views with alpha (the job tests' capture stage result), made
// once per test process under the test folder, in a folder of its own: ctest runs the tests of one
// binary as parallel processes, which must not replace each other's dataset.
inline fs::path tiny_dataset() {
  static const fs::path dir = [] {
    fs::path d = fs::path(LORGNETTE_TEST_TMP) / "service" / ("tiny-dataset-" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d.parent_path());
    const int status = run_cli({"-q", "synth", "--procedural", "--views", "8", "--size", "64x64", "--samples",
                                "1", "-o", d.string()},
                               d.string() + ".log");
    if (status != 0) throw std::runtime_error("synth failed; see " + d.string() + ".log");
    return d;
  }();
  return dir;
}
#endif

// The first bytes of an MP4 (an ISO "ftyp" box) followed by noise: accepted by the upload's check of
// its magic, then refused by the capture's decoder inside the worker.
inline std::string broken_mp4(size_t bytes = 2000) {
  return std::string(
             "\0\0\0\x18"
             "ftypmp42\0\0\0\0mp42isom",
             24) +
         std::string(bytes, 'x');
}

}  // namespace lorgnette::service::test
