// The `lorgnette` binary refusing out-of-range numbers (host/util/bounds.h) as a user types them:
// exit status 1, the flag named with its range on stderr, nothing hung and nothing written. Training
// and rendering check their flags before any dataset, model or device work, so dummy inputs suffice;
// the glasses and render cases run on a frame from `glasses make` and a tiny model written through
// the snapshot format.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/tools/cli_run.h"

namespace fs = std::filesystem;
using namespace lgn_cli_test;

namespace {

fs::path test_dir() { return lgn_cli_test::test_dir("cli_bounds"); }

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
  EXPECT_REFUSED(run_cli(d, base + "--neck-clear -0.1"), "--neck-clear must be within 0..1");
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

// Every numeric flag of every other command is checked against host/util/bounds.h before any input
// is read or output made: NaN and numbers outside the table are refused, naming the flag and its
// range (CLI11's own range checks let NaN through, and several flags had none).
TEST(CliBounds, MakingCommandsRefuseOutOfRangeNumbersAndWriteNothing) {
  fs::path d = test_dir();
  EXPECT_REFUSED(run_cli(d, "synth --procedural -o ds --specular nan"), "--specular must be within 0..2");
  EXPECT_REFUSED(run_cli(d, "synth --procedural -o ds --size 8x8"), "--size must be within 16..8192");
  EXPECT_REFUSED(run_cli(d, "synth --procedural -o ds --yaw-range -500 0"), "--yaw-range must be within");
  EXPECT_REFUSED(run_cli(d, "synth --procedural -o ds --views 0"), "--views must be within 1..100000");
  EXPECT_REFUSED(run_cli(d, "glasses make -o g.glb --metallic nan"), "--metallic must be within 0..1");
  EXPECT_REFUSED(run_cli(d, "glasses make -o g.glb --lens 5"), "--lens (Python: lens) must be within 30..80");
  EXPECT_REFUSED(run_cli(d, "capture nowhere -o cap --fps nan"), "--fps must be within 0.01..60");
  EXPECT_REFUSED(run_cli(d, "capture nowhere -o cap --max-features 0"), "--max-features must be within");
  EXPECT_REFUSED(run_cli(d, "demo -o demo --views 1"), "--views must be within 8..1000");
  EXPECT_REFUSED(run_cli(d, "demo -o demo --fit-views 1000"), "--fit-views must be within 2..200");
  for (const char* made : {"ds", "g.glb", "cap", "demo"}) EXPECT_FALSE(fs::exists(d / made)) << made;
}

TEST(CliBounds, ReadingCommandsRefuseOutOfRangeNumbersAndWriteNothing) {
  fs::path d = test_dir();
  write_file(d / "model.lnerf", "not a model: the flags are checked first");
  write_file(d / "frame.glb", "not a frame: the flags are checked first");
  EXPECT_REFUSED(run_cli(d, "view model.lnerf --glasses frame.glb --port 70000"),
                 "--port must be within 0..65535");
  EXPECT_REFUSED(run_cli(d, "view model.lnerf --glasses frame.glb --size 10x10"),
                 "--size must be within 32..1920");
  EXPECT_REFUSED(run_cli(d, "fit model.lnerf --glasses frame.glb -o p.json --yaw-range nan"),
                 "--yaw-range (Python: yaw_range) must be within 0..60");
  EXPECT_REFUSED(run_cli(d, "fit model.lnerf --glasses frame.glb -o p.json --views 1"),
                 "--views (Python: views) must be within 2..200");
  EXPECT_REFUSED(run_cli(d, "eval model.lnerf data -o ev --downscale 0"),
                 "--downscale (Python: downscale) must be within 1..16");
  EXPECT_REFUSED(run_cli(d, "eval model.lnerf data -o ev --max-views -1"), "--max-views must be within");
  EXPECT_REFUSED(run_cli(d, "bench frames --step-scale 1e-9 --out bench"),
                 "--step-scale (Python: step_scale) must be within 0.25..8");
  EXPECT_REFUSED(run_cli(d, "bench frames --repeats 0 --out bench"), "--repeats must be within 1..100");
  EXPECT_REFUSED(run_cli(d, "serve --data served --capture-fps nan"),
                 "--capture-fps must be within 0.01..60");
  EXPECT_REFUSED(run_cli(d, "serve --data served --port 70000"), "--port must be within 0..65535");
  EXPECT_REFUSED(run_cli(d, "serve --data served --fit-resolution 1"), "--fit-resolution must be within");
  for (const char* made : {"p.json", "ev", "bench", "served"}) EXPECT_FALSE(fs::exists(d / made)) << made;
}
