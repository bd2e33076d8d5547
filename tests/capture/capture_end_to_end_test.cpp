// End to end (LABELS slow, ~20 s): 12 consecutive fox photos (instant-ngp's sample capture) at
// 360x640 through frames -> COLMAP -> transforms.json; the recovered poses must match the provided
// transforms.json (COLMAP at full size by instant-ngp's authors) up to a similarity transform.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "capture/capture.h"
#include "capture/subprocess.h"
#include "eval/pose_compare.h"
#include "host/dataset/dataset.h"

namespace fs = std::filesystem;
using namespace lorgnette;
using namespace lorgnette::capture;

namespace {

const char* kFrames[] = {"0025", "0026", "0027", "0029", "0030", "0031",
                         "0033", "0034", "0035", "0039", "0042", "0044"};

}  // namespace

TEST(CaptureEndToEnd, FoxPosesMatchTheReferenceUpToASimilarity) {
  fs::path data = fs::path(LORGNETTE_DATA_DIR) / "nerf/fox";
  if (!fs::exists(data / "transforms.json")) GTEST_SKIP() << "fox data not found under " << data;
  if (find_executable("colmap").empty()) GTEST_SKIP() << "colmap is not installed (apt-get install colmap)";
  fs::path root = fs::path(LORGNETTE_TEST_TMP) / "capture" / "e2e_fox";
  fs::remove_all(root);
  fs::create_directories(root / "input");
  for (const char* f : kFrames)  // links, not copies: the data stays in the shared folder
    fs::create_symlink(data / "images" / (std::string(f) + ".jpg"),
                       root / "input" / (std::string(f) + ".jpg"));

  CaptureOptions opt;
  opt.input = (root / "input").string();
  opt.output = (root / "dataset").string();
  opt.frames.max_side = 640;
  opt.blink_filter = false;  // a fox: no human eyes to check
  opt.colmap.max_features = 2048;
  CaptureReport report = run_capture(opt);
  ASSERT_EQ(report.registered, std::size(kFrames)) << report.to_json().dump(2);

  PoseAccuracy acc = compare_poses(opt.output, (data / "transforms.json").string());
  EXPECT_EQ(acc.matched, std::size(kFrames));
  std::printf(
      "fox e2e: rotation error mean %.3f max %.3f deg; centre error mean %.2f%% max %.2f%% of "
      "the camera spread\n",
      acc.rotation_deg_mean, acc.rotation_deg_max, 100 * acc.centre_rel_mean, 100 * acc.centre_rel_max);
  EXPECT_LE(acc.rotation_deg_max, 2.0);
  // Centres: 12 views over a short arc at a third of the resolution; 5% of the mean distance of
  // the centres from their centroid is well above COLMAP's noise at sub-pixel reprojection error
  // and well below a wrong or mirrored pose.
  EXPECT_LE(acc.centre_rel_max, 0.05);
  dataset::LoadOptions lo;
  lo.load_images = false;
  dataset::Dataset ds = dataset::load_dataset(opt.output, lo);
  // Intrinsics: the reference fl_x (1375.52 px at 1080 wide) scaled to 360 wide, within 5%.
  EXPECT_NEAR(ds.frames[0].camera.fx, 1375.52 * 360.0 / 1080.0, 0.05 * 458.5);
  EXPECT_GT(report.subject_points, 50u);
  // No human face in the fox photos: the sparse-point box is written, with a warning saying why.
  EXPECT_EQ(report.aabb_from, "sparse points");
  EXPECT_TRUE(std::any_of(report.warnings.begin(), report.warnings.end(),
                          [](const std::string& w) { return w.find("no head box") != std::string::npos; }));
}
