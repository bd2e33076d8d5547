// The `lorgnette` binary run as a user runs it, on tiny inputs: exit status, what stderr says, and
// the files left behind. Covers the rule that existing outputs are never overwritten without
// --force, checked before any work (so a dummy model file is enough for the refusals), that --force
// replaces only a command's own earlier output, and that a full disk or a read-only folder is a
// clear error (a small tmpfs the test mounts).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/common/cli_run.h"
#include "tests/common/scoped_tmpfs.h"

namespace fs = std::filesystem;

namespace {

namespace lt = lorgnette::testing;
using lt::CliResult;
using lt::write_file;

// A fresh, empty directory for one test.
fs::path test_dir() {
  const fs::path d =
      fs::path(LORGNETTE_TEST_TMP) / "cli" / ::testing::UnitTest::GetInstance()->current_test_info()->name();
  for (const char* mount_point : {"ro", "full"})  // left mounted by a killed run
    ::umount2((d / mount_point).c_str(), MNT_DETACH);
  return lt::fresh_test_dir(LORGNETTE_TEST_TMP, "cli");
}

// Runs `lorgnette <args>` in `dir` (stdout is dropped, stderr kept).
CliResult cli(const fs::path& dir, const std::string& args) { return lt::run_cli(LGN_CLI_PATH, dir, args); }

#define EXPECT_CONTAINS(text, part) EXPECT_NE((text).find(part), std::string::npos) << "stderr: " << (text)

const std::string kKeep = "a file the user wants to keep\n";

}  // namespace

TEST(Cli, FitRefusesAnExistingPlacementBeforeLoadingAnything) {
  fs::path d = test_dir();
  write_file(d / "model.lnerf", "not a model");  // CLI11 only checks that these exist
  write_file(d / "frame.glb", "not a mesh");
  write_file(d / "placement.json", kKeep);
  CliResult r = cli(d, "fit model.lnerf --glasses frame.glb -o placement.json");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "'placement.json' exists");
  EXPECT_CONTAINS(r.err, "--force");
  EXPECT_EQ(lt::read(d / "placement.json"), kKeep);
  // The default output is placement.json too.
  r = cli(d, "fit model.lnerf --glasses frame.glb");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "--force");
  // With --force the check passes and the command gets as far as reading the (dummy) frame.
  r = cli(d, "fit model.lnerf --glasses frame.glb -o placement.json --force");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err.find("--force"), std::string::npos) << r.err;
  EXPECT_EQ(lt::read(d / "placement.json"), kKeep);
}

TEST(Cli, FitRefusesADebugDirectoryWithAnEarlierFitsViews) {
  fs::path d = test_dir();
  write_file(d / "model.lnerf", "not a model");
  write_file(d / "frame.glb", "not a mesh");
  fs::create_directories(d / "debug");
  write_file(d / "debug" / "view_03.png", kKeep);
  CliResult r = cli(d, "fit model.lnerf --glasses frame.glb -o placement.json --debug debug");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "view_03.png");
  EXPECT_CONTAINS(r.err, "--force");
  EXPECT_EQ(lt::read(d / "debug" / "view_03.png"), kKeep);
  // Other files in the directory are no obstacle: the command goes on to the (dummy) frame.
  fs::remove(d / "debug" / "view_03.png");
  write_file(d / "debug" / "notes.txt", kKeep);
  r = cli(d, "fit model.lnerf --glasses frame.glb -o placement.json --debug debug");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err.find("debug views"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "placement.json"));
}

// A frame narrower than unit detection's adult range (105-185 mm) keeps its size: the sidecar states
// the unit, so 2 x 30 + 14 + 6 = 80 mm is not read as some other unit's 140 mm.
TEST(Cli, GlassesMakeKeepsANarrowFramesSize) {
  fs::path d = test_dir();
  lt::CliCall call;
  call.stdout_to = "frame.json";
  CliResult r = lt::run_cli(LGN_CLI_PATH, d, "glasses make --lens 30 --bridge 14 -o narrow.glb --json", call);
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string out = lt::read(d / "frame.json");
  const size_t at = out.find("\"total_width\":");
  ASSERT_NE(at, std::string::npos) << out;
  EXPECT_NEAR(std::atof(out.c_str() + at + 14), 80.3, 0.5) << out;
  EXPECT_CONTAINS(lt::read(d / "narrow.glb.refpoints.json"), "\"mm_per_unit\": 1000");
}

TEST(Cli, GlassesMakeRefusesExistingOutputsUnlessForced) {
  fs::path d = test_dir();
  write_file(d / "frame.glb", kKeep);
  CliResult r = cli(d, "glasses make --temple 140 -o frame.glb");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "'frame.glb' exists");
  EXPECT_CONTAINS(r.err, "--force");
  EXPECT_EQ(lt::read(d / "frame.glb"), kKeep);
  EXPECT_FALSE(fs::exists(d / "frame.glb.refpoints.json"));

  // A new name works; a second run into the same name is refused (the .glb and its sidecar).
  r = cli(d, "glasses make --temple 140 -o new.glb");
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string made = lt::read(d / "new.glb");
  EXPECT_EQ(made.substr(0, 4), "glTF");
  ASSERT_TRUE(fs::exists(d / "new.glb.refpoints.json"));
  fs::remove(d / "new.glb");  // a stale sidecar alone is an output too
  r = cli(d, "glasses make --temple 140 -o new.glb");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "new.glb.refpoints.json' exists");

  write_file(d / "preview.png", kKeep);
  r = cli(d, "glasses make -o other.glb --preview preview.png");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "--preview");
  EXPECT_FALSE(fs::exists(d / "other.glb")) << "nothing is written when one output is refused";
  EXPECT_EQ(lt::read(d / "preview.png"), kKeep);

  r = cli(d, "glasses make --temple 140 -o frame.glb --force");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(lt::read(d / "frame.glb").substr(0, 4), "glTF");
}

TEST(Cli, GlassesInspectRefusesAnExistingPreview) {
  fs::path d = test_dir();
  ASSERT_EQ(cli(d, "glasses make -o frame.glb").status, 0);
  write_file(d / "preview.png", kKeep);
  CliResult r = cli(d, "glasses inspect frame.glb -o preview.png");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "'preview.png' exists");
  EXPECT_EQ(lt::read(d / "preview.png"), kKeep);
  r = cli(d, "glasses inspect frame.glb -o preview.png --force");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(lt::read(d / "preview.png").substr(1, 3), "PNG");
}

TEST(Cli, EvalRefusesADirectoryWithEvaluationImages) {
  fs::path d = test_dir();
  write_file(d / "model.lnerf", "not a model");
  fs::create_directories(d / "data");
  fs::create_directories(d / "eval");
  write_file(d / "eval" / "000_pred_truth_error.png", kKeep);
  CliResult r = cli(d, "eval model.lnerf data -o eval");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "evaluation images");
  EXPECT_CONTAINS(r.err, "--force");
  EXPECT_EQ(lt::read(d / "eval" / "000_pred_truth_error.png"), kKeep);
  // --force gets past the check to the (dummy) model.
  r = cli(d, "eval model.lnerf data -o eval --force");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err.find("evaluation images"), std::string::npos) << r.err;
}

TEST(Cli, RenderRefusesExistingFramesBeforeLoadingTheModel) {
  fs::path d = test_dir();
  write_file(d / "model.lnerf", "not a model");
  fs::create_directories(d / "out");
  write_file(d / "out" / "frame_0002.png", kKeep);
  CliResult r = cli(d, "render model.lnerf --orbit 4 -o out");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "frame_0002.png");
  EXPECT_CONTAINS(r.err, "--force");
  EXPECT_EQ(lt::read(d / "out" / "frame_0002.png"), kKeep);
  // A single --pose view writes frame_0000 only, so frame_0002 is no obstacle: the (dummy) model is.
  write_file(d / "pose.json", R"({"transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,2],[0,0,0,1]]})");
  r = cli(d, "render model.lnerf --pose pose.json -o out");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err.find("--force"), std::string::npos) << r.err;
  // --force gets past the check to the (dummy) model.
  r = cli(d, "render model.lnerf --orbit 4 -o out --force");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err.find("already holds"), std::string::npos) << r.err;
  EXPECT_EQ(lt::read(d / "out" / "frame_0002.png"), kKeep);
}

// --front is checked before the model is loaded: it needs --orbit and must be a direction.
TEST(Cli, RenderFrontNeedsAnOrbitAndADirection) {
  fs::path d = test_dir();
  write_file(d / "model.lnerf", "not a model");
  write_file(d / "pose.json", R"({"transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,2],[0,0,0,1]]})");
  CliResult r = cli(d, "render model.lnerf --pose pose.json --front 0 0 1 -o out");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "give --orbit N too");
  r = cli(d, "render model.lnerf --orbit 4 --front 0 0 0 -o out");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "--front 0 0 0 is not a direction");
  // A good one gets as far as the (dummy) model.
  r = cli(d, "render model.lnerf --orbit 4 --front 0 0.2 1 -o out");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err.find("--front"), std::string::npos) << r.err;
  EXPECT_CONTAINS(r.err, "model.lnerf");
}

// `bench frames` on the analytic head with a made frame: one command, a CSV and a chart per device
// (every row with the frame's split and both rates), and the files are not overwritten by a rerun.
TEST(Cli, BenchFramesWritesCsvAndChartPerDeviceAndKeepsThem) {
  fs::path d = test_dir();
  ASSERT_EQ(cli(d, "glasses make --temple 140 -o frame.glb").status, 0);
  const std::string bench = "bench frames --glasses frame.glb --sizes 64x36 --repeats 1 --compare --out out";
  CliResult r = cli(d, bench);
  ASSERT_EQ(r.status, 0) << r.err;
  std::vector<fs::path> csvs;
  for (const auto& e : fs::directory_iterator(d / "out"))
    if (e.path().extension() == ".csv") csvs.push_back(e.path());
  ASSERT_FALSE(csvs.empty());
  for (const fs::path& csv : csvs) {
    fs::path png = csv;
    png.replace_extension(".png");
    EXPECT_TRUE(fs::exists(png)) << png;
    std::string text = lt::read(csv);
    for (const char* column : {"median_ms", "march_ms", "surface_ms", "surface_wait_ms", "transfer_ms",
                               "samples_per_second", "composited_per_second", "variant"})
      EXPECT_CONTAINS(text, column);
    // Head alone: default and baseline (their waves differ); with glasses: default, sequential, baseline.
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1 + 2 + 3) << text;
  }
  const std::string before = lt::read(csvs[0]);
  r = cli(d, bench);
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "already holds");
  EXPECT_CONTAINS(r.err, "--out");
  EXPECT_CONTAINS(r.err, "--force");
  EXPECT_EQ(lt::read(csvs[0]), before);
}

// `bench frames --marcher auto,fused` times both marchers side by side, and each row names the
// kernels that marched it (auto is the wavefront marcher on a CPU); a word that is no marcher is a
// clear error.
TEST(Cli, BenchFramesTimesSeveralMarchersSideBySide) {
  fs::path d = test_dir();
  ASSERT_EQ(cli(d, "glasses make --temple 140 -o frame.glb").status, 0);
  CliResult r = cli(d,
                    "--device 0 bench frames --glasses frame.glb --sizes 64x36 --repeats 1 --compare "
                    "--marcher auto,fused --out out");
  ASSERT_EQ(r.status, 0) << r.err;
  std::vector<fs::path> csvs;
  for (const auto& e : fs::directory_iterator(d / "out"))
    if (e.path().extension() == ".csv") csvs.push_back(e.path());
  ASSERT_EQ(csvs.size(), 1u);
  std::istringstream text(lt::read(csvs[0]));
  std::string line;
  std::getline(text, line);
  EXPECT_CONTAINS(line, ",marcher,");
  std::map<std::string, int> rows;  // marcher -> rows
  while (std::getline(text, line))
    for (const char* m : {",wavefront,", ",fused,"})
      if (line.find(m) != std::string::npos) rows[m]++;
  // Per marcher: head alone default and baseline, with glasses default, sequential and baseline.
  EXPECT_EQ(rows[",wavefront,"], 5) << lt::read(csvs[0]);
  EXPECT_EQ(rows[",fused,"], 5) << lt::read(csvs[0]);
  r = cli(d, "bench frames --sizes 64x36 --repeats 1 --marcher auto,warp --out out2");
  EXPECT_NE(r.status, 0);
  EXPECT_CONTAINS(r.err, "'warp' is not a marcher");
}

namespace {
const std::string kTinySynth = "synth --procedural --views 1 --size 16x16 --samples 1";
}  // namespace

TEST(Cli, SynthForceReplacesOnlyAnEarlierSynthOutput) {
  fs::path d = test_dir();
  fs::create_directories(d / "photos");
  write_file(d / "photos" / "mine.jpg", kKeep);
  CliResult r = cli(d, kTinySynth + " -o photos --force");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "is not an earlier synthetic dataset");
  EXPECT_EQ(lt::read(d / "photos" / "mine.jpg"), kKeep);
  // Its own earlier output: refused without --force, replaced with it.
  r = cli(d, kTinySynth + " -o data");
  ASSERT_EQ(r.status, 0) << r.err;
  r = cli(d, kTinySynth + " -o data");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "--force");
  r = cli(d, kTinySynth + " -o data --force");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(d / "data" / "transforms.json"));
}

TEST(Cli, SynthIntoTheWorkingDirectoryIsRefused) {
  fs::path d = test_dir();
  write_file(d / "notes.txt", kKeep);
  CliResult r = cli(d, kTinySynth + " -o . --force");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "working directory");
  EXPECT_EQ(lt::read(d / "notes.txt"), kKeep);
  // An empty working directory too: the dataset would replace the folder the shell stands in.
  fs::create_directories(d / "empty");
  r = cli(d / "empty", kTinySynth + " -o .");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "working directory");
  EXPECT_TRUE(fs::is_directory(d / "empty"));
}

// --hair and --window as a user types them: a colour that is not r,g,b or lies outside 0..255, hair
// on a mesh and a window outside the plain room are refused with what to give instead, before
// anything is written; a good run records the hair's albedo (sRGB 244,242,238 -> linear, within
// float rounding) and the window in ground_truth.json.
TEST(Cli, SynthHairAndWindow) {
  fs::path d = test_dir();
  const std::string room = kTinySynth + " --room 3 -o ds";
  CliResult r = cli(d, room + " --hair 300,0,0");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "--hair component 300 is outside 0..255");
  r = cli(d, room + " --hair blond");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "--hair 'blond' is not r,g,b");
  r = cli(d, "synth --mesh head.glb -o ds --hair 10,10,10");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "give --procedural");
  r = cli(d, kTinySynth + " --room 1 -o ds --window");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "give --room 3");
  EXPECT_FALSE(fs::exists(d / "ds"));
  r = cli(d, room + " --window --wall 244,242,238 --hair 244,242,238");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json gt = nlohmann::json::parse(std::ifstream(d / "ds" / "ground_truth.json"));
  const nlohmann::json& hair = gt.at("params").at("hair_linear");
  const nlohmann::json& wall = gt.at("room").at("wall_rgb");
  for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(hair[k].get<float>(), wall[k].get<float>()) << k;
  EXPECT_NEAR(hair[0].get<float>(), 0.9047f, 1e-4f);  // sRGB 244 -> linear
  EXPECT_TRUE(gt.at("room").at("window").is_object()) << gt.at("room").dump();
}

// The model's folder is checked before the dataset is read (the dataset here does not exist: a
// later check would complain about it instead).
TEST(Cli, TrainChecksTheModelFolderBeforeAnyWork) {
  fs::path d = test_dir();
  lgn_test::ScopedTmpfs read_only(d / "ro", 64 * 1024, true);
  LGN_SKIP_UNLESS_MOUNTED(read_only);
  CliResult r = cli(d, "train no-such-dataset -o ro/head.lnerf");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "cannot write the model (-o ro/head.lnerf)");
  EXPECT_CONTAINS(r.err, "Read-only file system");
  lgn_test::ScopedTmpfs full(d / "full", 64 * 1024);
  LGN_SKIP_UNLESS_MOUNTED(full);
  full.fill();
  r = cli(d, "train no-such-dataset -o full/head.lnerf");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "No space left on device");
  EXPECT_FALSE(fs::exists(d / "full" / "head.lnerf"));
}

// A training checkpoint beside the model is an unfinished training: a new training without --resume
// is refused before any work (nothing of it is written over), as is --resume onto a model that has
// no checkpoint (it would be written over); the dataset does not exist, so a later check would
// complain about it instead.
TEST(Cli, TrainRefusesToWriteOverAnUnfinishedTrainingWithoutResume) {
  fs::path d = test_dir();
  write_file(d / "head.lnerf.ckpt", "a checkpoint");
  CliResult r = cli(d, "train no-such-dataset -o head.lnerf");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "'head.lnerf.ckpt' holds an unfinished training of 'head.lnerf': pass --resume");
  EXPECT_EQ(lt::read(d / "head.lnerf.ckpt"), "a checkpoint");
  r = cli(d, "train no-such-dataset -o head.lnerf --resume");  // taken: the dataset is what fails
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err.find("unfinished training"), std::string::npos) << r.err;
  fs::remove(d / "head.lnerf.ckpt");
  write_file(d / "head.lnerf", "a model");
  r = cli(d, "train no-such-dataset -o head.lnerf --resume");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "'head.lnerf' exists: pass --force");
  EXPECT_EQ(lt::read(d / "head.lnerf"), "a model");
}

TEST(Cli, GlassesPreviewOnAFullDiskIsAnError) {
  fs::path d = test_dir();
  CliResult r = cli(d, "glasses make -o frame.glb");
  ASSERT_EQ(r.status, 0) << r.err;
  lgn_test::ScopedTmpfs full(d / "full", 64 * 1024);
  LGN_SKIP_UNLESS_MOUNTED(full);
  full.fill();
  r = cli(d, "glasses inspect frame.glb -o full/preview.png");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "No space left on device");
  EXPECT_FALSE(fs::exists(d / "full" / "preview.png"));
  r = cli(d, "glasses make -o full/other.glb");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "No space left on device");
  EXPECT_FALSE(fs::exists(d / "full" / "other.glb"));
}

// `render -o DIR` onto a full disk or into a read-only folder: a clear error before the model is
// loaded (the dummy model is never read), exit 1, and no DIR left behind (an empty folder would look
// like a render that produced nothing). A disk that fills later is render_job_test's.
TEST(Cli, RenderOnAFullDiskLeavesNoFolder) {
  fs::path d = test_dir();
  write_file(d / "model.lnerf", "not a model");
  lgn_test::ScopedTmpfs full(d / "full", 64 * 1024);
  LGN_SKIP_UNLESS_MOUNTED(full);
  full.fill();
  CliResult r = cli(d, "render model.lnerf --orbit 4 -o full/renders");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "No space left on device");
  EXPECT_CONTAINS(r.err, "-o full/renders");
  EXPECT_FALSE(fs::exists(d / "full" / "renders"));
  lgn_test::ScopedTmpfs read_only(d / "ro", 64 * 1024, true);
  LGN_SKIP_UNLESS_MOUNTED(read_only);
  r = cli(d, "render model.lnerf --orbit 4 -o ro/renders");
  EXPECT_EQ(r.status, 1);
  EXPECT_CONTAINS(r.err, "Read-only file system");
  EXPECT_FALSE(fs::exists(d / "ro" / "renders"));
}
