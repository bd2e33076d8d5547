// The `lorgnette` binary refusing out-of-range numbers (host/util/bounds.h) as a user types them:
// exit status 1, the flag named with its range on stderr, nothing hung and nothing written. Training
// and rendering check their flags before any dataset, model or device work, so dummy inputs suffice;
// the glasses and render cases run on a frame from `glasses make` and a tiny model written through
// the snapshot format.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "host/nerf/snapshot.h"
#include "tests/common/cli_run.h"

namespace fs = std::filesystem;

namespace {

namespace lt = lorgnette::testing;
using lt::CliResult;
using lt::write_file;

fs::path test_dir() { return lt::fresh_test_dir(LORGNETTE_TEST_TMP, "cli_bounds"); }

// Runs `lorgnette -q <args>` in `dir` with a 60 s limit (a hang exits 124).
CliResult run_cli(const fs::path& dir, const std::string& args) {
  lt::CliCall call;
  call.timeout_s = 60;
  return lt::run_cli(LGN_CLI_PATH, dir, "-q " + args, call);
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
void write_tiny_model(const fs::path& path) {
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

void write_pose(const fs::path& path) {
  write_file(path, R"({"transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,4],[0,0,0,1]], "fov_y_deg": 30})");
}

}  // namespace

TEST(CliBounds, TrainRefusesOutOfRangeNumbersBeforeLoadingAnything) {
  fs::path d = test_dir();
  fs::create_directories(d / "data");  // never read: the flags are checked first
  const std::string base = "train data -o m.lnerf ";
  EXPECT_REFUSED(run_cli(d, base + "--steps 0"), "--steps (Python: steps) must be within 1..1e+07");
  EXPECT_REFUSED(run_cli(d, base + "--seconds nan"),
                 "--seconds (Python: seconds) must be within 0.1..604800");
  EXPECT_REFUSED(run_cli(d, base + "--aabb=-1e30,-1,-1,1e30,1,1"), "--aabb must be within -100000..100000");
  EXPECT_REFUSED(run_cli(d, base + "--downscale 1000"),
                 "--downscale (Python: downscale) must be within 1..16");
  EXPECT_REFUSED(run_cli(d, base + "--step 1e-9"), "--step must be within 1e-06..10000");
  EXPECT_REFUSED(run_cli(d, base + "--lr nan"), "--lr must be within");
  EXPECT_REFUSED(run_cli(d, base + "--hair 5000"), "--hair (Python: hair_mm) must be within 0..300");
  EXPECT_FALSE(fs::exists(d / "m.lnerf"));
}

TEST(CliBounds, RenderRefusesOutOfRangeNumbersBeforeLoadingTheModel) {
  fs::path d = test_dir();
  write_file(d / "model.lnerf", "not a model: the flags are checked first");
  write_pose(d / "pose.json");
  CliResult r = run_cli(d, "render model.lnerf --orbit 1000000000 -o out");
  EXPECT_REFUSED(r, "--orbit (Python: views) must be within 1..3600");
  EXPECT_LT(r.seconds, 30.0);
  EXPECT_REFUSED(run_cli(d, "render model.lnerf --orbit 4 --background nan nan nan -o out"),
                 "--background (Python: background) must be within 0..1");
  EXPECT_REFUSED(run_cli(d, "render model.lnerf --pose pose.json --step-scale 1e-9 -o out"),
                 "--step-scale (Python: step_scale) must be within 0.25..8");
  EXPECT_REFUSED(run_cli(d, "render model.lnerf --pose pose.json --spp 0 -o out"), "--spp (Python: spp)");
  EXPECT_REFUSED(run_cli(d, "render model.lnerf --pose pose.json --fov 500 -o out"), "--fov");
  EXPECT_FALSE(fs::exists(d / "out"));
}

TEST(CliBounds, GlassesRefuseBadUnitsAndSidecarNumbers) {
  fs::path d = test_dir();
  ASSERT_EQ(run_cli(d, "glasses make -o frame.glb").status, 0);
  EXPECT_REFUSED(run_cli(d, "glasses inspect frame.glb --mm-per-unit -1"),
                 "--mm-per-unit (Python: mm_per_unit) must be within 0.001..100000");
  EXPECT_REFUSED(run_cli(d, "glasses inspect frame.glb --mm-per-unit nan"), "--mm-per-unit");
  ASSERT_EQ(run_cli(d, "glasses inspect frame.glb").status, 0);
  write_file(d / "frame.glb.refpoints.json",
             R"({"version": 1, "g_c": [0, 0, 0], "g_l": [1e300, 0, 0], "g_r": [-0.07, 0, -0.1]})");
  EXPECT_REFUSED(run_cli(d, "glasses inspect frame.glb --json"), "'g_l' must hold coordinates within");
  write_file(d / "frame.glb.refpoints.json",
             R"({"version": 1, "g_c": [0, 0, 0], "g_l": [0.07, 0, -0.1], "g_r": [-0.07, 0, -0.1],
                 "mm_per_unit": -1})");
  EXPECT_REFUSED(run_cli(d, "glasses inspect frame.glb"), "'mm_per_unit' must be within 0.001..100000");
}

// `render` used to drop a frame whose sidecar held 1e300 and exit 0; now it refuses, as it refuses
// glasses with no placement (which drew the frame at the identity, a slab over the face).
TEST(CliBounds, RenderRefusesABrokenSidecarAndGlassesWithoutAPlacement) {
  fs::path d = test_dir();
  write_tiny_model(d / "head.lnerf");
  write_pose(d / "pose.json");
  ASSERT_EQ(run_cli(d, "glasses make -o frame.glb").status, 0);
  EXPECT_REFUSED(run_cli(d, "render head.lnerf --glasses frame.glb --pose pose.json --size 16x16 -o out"),
                 "glasses were given but no placement");
  write_file(d / "frame.glb.refpoints.json",
             R"({"version": 1, "g_c": [0, 0, 0], "g_l": [1e300, 0, 0], "g_r": [-0.07, 0, -0.1]})");
  EXPECT_REFUSED(run_cli(d,
                         "render head.lnerf --glasses frame.glb --translate 0 0 0 --scale 0.001 --pose "
                         "pose.json --size 16x16 -o out"),
                 "'g_l' must hold coordinates within");
  EXPECT_FALSE(fs::exists(d / "out" / "frame_0000.png"));
}
