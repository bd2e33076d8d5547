// The second careless-user sweep of issue #42, as tests of the `lorgnette` binary: an output named
// the same as one of the command's inputs is refused before any work, with --force too (the input
// would be lost), and nothing is written; SIGTERM stops a long evaluation promptly. The inputs are a frame
// from `glasses make`, a tiny model written through the snapshot format and a one-view synthetic dataset.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tests/tools/cli_run.h"

namespace fs = std::filesystem;
using namespace lgn_cli_test;

namespace {

fs::path test_dir() { return lgn_cli_test::test_dir("cli_sweep"); }

struct Stopped {
  int status = -1, stop_ms = -1;  // the exit status; milliseconds from SIGTERM to the exit
  std::string err;
};

// Runs `lorgnette -q <args>` in `dir`, sends SIGTERM after `after_s` seconds and waits for the exit
// (a shell script does the timing; the whole run is killed after 120 s).
// `started` (a shell glob, relative to `dir`) names a file the command writes once its work is
// under way: the signal waits for it (as long as the command runs), so a loaded machine that is
// slow to start does not turn the test into one about start-up.
Stopped stop_after(const fs::path& dir, const std::string& args, int after_s,
                   const std::string& started = "") {
  const std::string wait_started = started.empty() ? ""
                                                   : "while kill -0 $p 2>/dev/null && ! ls " + started +
                                                         " >/dev/null 2>&1; do sleep 0.2; done; ";
  write_file(dir / "stop.sh", "'" LGN_CLI_PATH "' -q " + args + " 2> stderr.txt & p=$!; " + wait_started +
                                  "sleep " + std::to_string(after_s) +
                                  "; t0=$(date +%s%N); kill -TERM $p; wait $p; s=$?; t1=$(date +%s%N); "
                                  "echo $s $(( (t1 - t0) / 1000000 )) > result.txt");
  Stopped r;
  if (std::system(("cd '" + dir.string() + "' && timeout -s KILL 120 sh stop.sh").c_str()) != 0) return r;
  std::istringstream result(read_file(dir / "result.txt"));
  result >> r.status >> r.stop_ms;
  r.err = read_file(dir / "stderr.txt");
  return r;
}

// No hidden temporary file is left in `dir` (the atomic writer's, or a staging folder's).
void expect_no_temporary_files(const fs::path& dir) {
  if (!fs::is_directory(dir)) return;
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_NE(e.path().filename().string()[0], '.') << "a temporary file was left: " << e.path();
}

}  // namespace

TEST(CliSweep, FitNeverWritesItsPlacementOverItsInputs) {
  fs::path d = test_dir();
  write_tiny_model(d / "head.lnerf");
  ASSERT_EQ(run_cli(d, "glasses make -o frame.glb").status, 0);
  const std::string model = read_file(d / "head.lnerf"), frame = read_file(d / "frame.glb");
  for (const char* target : {"head.lnerf", "frame.glb", "frame.glb.refpoints.json", "./sub/../head.lnerf"}) {
    CliResult r = run_cli(d, std::string("fit head.lnerf --glasses frame.glb --force -o ") + target);
    EXPECT_REFUSED(r, "is the input");
    EXPECT_LT(r.seconds, 20.0) << "refused before the fit";
  }
  EXPECT_EQ(read_file(d / "head.lnerf"), model);
  EXPECT_EQ(read_file(d / "frame.glb"), frame);
}

TEST(CliSweep, GlassesPreviewsNeverReplaceTheFrame) {
  fs::path d = test_dir();
  ASSERT_EQ(run_cli(d, "glasses make -o frame.glb").status, 0);
  const std::string frame = read_file(d / "frame.glb");
  EXPECT_REFUSED(run_cli(d, "glasses inspect frame.glb -o frame.glb --force"), "is the input");
  EXPECT_EQ(read_file(d / "frame.glb"), frame);
  // `make` with its preview named as its own output: refused before the frame is written.
  EXPECT_REFUSED(run_cli(d, "glasses make -o other.glb --preview other.glb"), "is the input");
  EXPECT_FALSE(fs::exists(d / "other.glb"));
  EXPECT_FALSE(fs::exists(d / "other.glb.refpoints.json"));
}

TEST(CliSweep, TrainNeverWritesItsModelOverTheDataset) {
  fs::path d = test_dir();
  ASSERT_EQ(run_cli(d, "synth --procedural --views 1 --size 16x16 --samples 1 -o data").status, 0);
  const std::string transforms = read_file(d / "data" / "transforms.json");
  for (const char* target : {"data/transforms.json", "data/ground_truth.json"}) {
    CliResult r = run_cli(d, std::string("train data --steps 1 --force -o ") + target);
    EXPECT_REFUSED(r, "is the input");
  }
  CliResult r = run_cli(d, "train data/transforms.json --steps 1 --force -o data/transforms.json");
  EXPECT_REFUSED(r, "is the input");
  EXPECT_EQ(read_file(d / "data" / "transforms.json"), transforms);
}

// SIGTERM (a service or a shell stopping the process) ends a long evaluation at the next view: exit
// status 130, within seconds, and the comparison images written so far are whole files (no
// temporary file is left). The 100 held-out views render a tiny model over 256 x 256 images, minutes
// of work that used to run to the end whatever the signal said.
TEST(CliSweep, EvalStopsPromptlyOnSigterm) {
  fs::path d = test_dir();
  write_tiny_model(d / "head.lnerf");
  ASSERT_EQ(run_cli(d, "synth --procedural --views 1 --size 256x256 --samples 1 -o data").status, 0);
  nlohmann::json t = nlohmann::json::parse(read_file(d / "data" / "transforms.json"));
  nlohmann::json frames = nlohmann::json::array();
  for (int i = 0; i < 800; ++i) {  // every 8th is held out: 100 views, from (slightly) apart cameras
    nlohmann::json f = t["frames"][0];
    f["transform_matrix"][0][3] = f["transform_matrix"][0][3].get<double>() + 1e-3 * i;
    frames.push_back(f);
  }
  t["frames"] = frames;
  write_file(d / "data" / "transforms.json", t.dump());
  Stopped r = stop_after(d, "eval head.lnerf data -o ev", 4);
  EXPECT_EQ(r.status, 130) << r.err;
  EXPECT_LT(r.stop_ms, 15000) << "it stopped " << r.stop_ms << " ms after SIGTERM";
  EXPECT_NE(r.err.find("interrupted"), std::string::npos) << r.err;
  expect_no_temporary_files(d / "ev");
}

// The same for an orbit render: it stops at the next frame, and every frame written is whole.
TEST(CliSweep, RenderOrbitStopsPromptlyOnSigtermWithWholeFrames) {
  fs::path d = test_dir();
  write_tiny_model(d / "head.lnerf");
  Stopped r = stop_after(d, "render head.lnerf --orbit 500 --size 256x256 -o orbit", 1, "orbit/frame_*.png");
  EXPECT_EQ(r.status, 130) << r.err;
  EXPECT_LT(r.stop_ms, 15000) << "it stopped " << r.stop_ms << " ms after SIGTERM";
  expect_no_temporary_files(d / "orbit");
  int frames = 0;
  for (const auto& e : fs::directory_iterator(d / "orbit"))
    if (e.path().extension() == ".png" && e.path().filename().string().rfind("frame_", 0) == 0) {
      ++frames;
      EXPECT_GT(fs::file_size(e.path()), 100u) << e.path();
    }
  EXPECT_LT(frames, 500) << "the orbit ran to its end";
}

TEST(CliSweep, PathsWithSpacesAndNonAsciiLettersWork) {
  fs::path d = test_dir();
  fs::create_directories(d / "my frames");
  ASSERT_EQ(run_cli(d, "glasses make -o \"my frames/fr\xC3\xA4me 1.glb\"").status, 0);
  CliResult r =
      run_cli(d, "glasses inspect \"my frames/fr\xC3\xA4me 1.glb\" -o \"my frames/pr\xC3\xA9view 1.png\"");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_GT(fs::file_size(d / "my frames" / "pr\xC3\xA9view 1.png"), 1000u);
  EXPECT_REFUSED(
      run_cli(d,
              "glasses inspect \"my frames/fr\xC3\xA4me 1.glb\" -o \"my frames/fr\xC3\xA4me 1.glb\" --force"),
      "is the input");
}

// Empty and truncated inputs of every kind are refused with the file's name and the reason, exit
// status 1, and nothing is written.
TEST(CliSweep, EmptyAndTruncatedInputsAreRefusedAndNothingIsWritten) {
  fs::path d = test_dir();
  write_tiny_model(d / "head.lnerf");
  ASSERT_EQ(run_cli(d, "glasses make -o frame.glb").status, 0);
  write_file(d / "empty.lnerf", "");
  write_file(d / "short.lnerf", read_file(d / "head.lnerf").substr(0, 200));
  write_file(d / "short.glb", read_file(d / "frame.glb").substr(0, 1000));
  write_file(d / "empty.json", "");
  write_file(d / "short.json", R"({"version": 1, "transform": [[1, 0)");
  write_file(d / "pose.json",
             R"({"transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,4],[0,0,0,1]], "fov_y_deg": 30})");
  fs::create_directories(d / "data");
  write_file(d / "data" / "transforms.json", R"({"frames": [)");
  write_file(d / "empty.mp4", "");
  EXPECT_REFUSED(run_cli(d, "render empty.lnerf --pose pose.json -o out"), "'empty.lnerf' is corrupt");
  EXPECT_REFUSED(run_cli(d, "render short.lnerf --pose pose.json -o out"), "'short.lnerf'");
  EXPECT_REFUSED(run_cli(d, "fit empty.lnerf --glasses frame.glb -o p.json"), "'empty.lnerf' is corrupt");
  EXPECT_REFUSED(run_cli(d, "glasses inspect short.glb -o prev.png"), "'short.glb'");
  EXPECT_REFUSED(
      run_cli(d, "render head.lnerf --glasses frame.glb --placement empty.json --pose pose.json -o out"),
      "'empty.json' is not valid JSON");
  EXPECT_REFUSED(
      run_cli(d, "render head.lnerf --glasses frame.glb --placement short.json --pose pose.json -o out"),
      "'short.json' is not valid JSON");
  EXPECT_REFUSED(run_cli(d, "render head.lnerf --pose empty.json -o out"), "'empty.json' is not valid JSON");
  EXPECT_REFUSED(run_cli(d, "train data --steps 1 -o m.lnerf"), "transforms.json' is not valid JSON");
  EXPECT_REFUSED(run_cli(d, "eval head.lnerf data"), "transforms.json' is not valid JSON");
  EXPECT_REFUSED(run_cli(d, "capture empty.mp4 -o cap"), "cannot open video 'empty.mp4'");
  for (const char* made : {"out", "p.json", "prev.png", "m.lnerf", "cap"})
    EXPECT_FALSE(fs::exists(d / made)) << made;
}
