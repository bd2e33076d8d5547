// Bad input to `lorgnette capture` gives clear errors: a missing input, a folder without images, an
// unreadable video, COLMAP missing (a PATH without it), COLMAP failing (a fake script that exits 3),
// COLMAP finding no model; and several disconnected models keep the largest with a warning. An earlier
// capture is replaced only with --force; a COLMAP model whose images are partly missing from the
// folder loses those frames (named in a warning), or is refused when too few remain.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "capture/capture.h"
#include "tests/capture/synthetic_model.h"

namespace fs = std::filesystem;
using namespace lorgnette::capture;

namespace {

using synthetic::tmp_dir;

// Runs `f` and returns its exception's message ("" when it did not throw).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

#define EXPECT_CONTAINS(text, part) \
  EXPECT_NE(std::string(text).find(part), std::string::npos) << "message: " << (text)

class CaptureErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    const char* p = std::getenv("PATH");
    saved_path_ = p ? p : "";
    input_ = tmp_dir(std::string("in_") + name());
    for (int i = 0; i < 4; ++i) {
      cv::Mat img(60, 80, CV_8UC3);
      cv::RNG(10 + i).fill(img, cv::RNG::UNIFORM, 0, 256);
      cv::imwrite((input_ / ("img_" + std::to_string(i) + ".png")).string(), img);
    }
    output_ = fs::path(LORGNETTE_TEST_TMP) / "capture" / (std::string("out_") + name());
    fs::remove_all(output_);
    opt_.input = input_.string();
    opt_.output = output_.string();
    opt_.blink_filter = false;
  }
  void TearDown() override { setenv("PATH", saved_path_.c_str(), 1); }
  static const char* name() { return ::testing::UnitTest::GetInstance()->current_test_info()->name(); }
  // A fake `colmap` (shell script) first on PATH.
  void fake_colmap(const std::string& body) {
    fs::path bin = tmp_dir(std::string("bin_") + name());
    std::ofstream(bin / "colmap") << "#!/bin/sh\n" << body << "\n";
    fs::permissions(bin / "colmap", fs::perms::owner_all);
    setenv("PATH", (bin.string() + ":/usr/bin:/bin").c_str(), 1);
  }
  std::string saved_path_;
  fs::path input_, output_;
  CaptureOptions opt_;
};

}  // namespace

TEST_F(CaptureErrors, MissingInput) {
  opt_.input = (input_ / "nope").string();
  EXPECT_CONTAINS(error_of([&] { run_capture(opt_); }), "does not exist");
}

TEST_F(CaptureErrors, FolderWithoutImages) {
  opt_.input = tmp_dir("empty_folder").string();
  EXPECT_CONTAINS(error_of([&] { run_capture(opt_); }), "no images");
}

TEST_F(CaptureErrors, UnreadableVideo) {
  fs::path video = input_ / "clip.mp4";
  std::ofstream(video) << "this is not a video";
  opt_.input = video.string();
  std::string e = error_of([&] { run_capture(opt_); });
  EXPECT_CONTAINS(e, "video");
  EXPECT_CONTAINS(e, "clip.mp4");
}

TEST_F(CaptureErrors, ColmapMissingNamesTheDebianPackage) {
  setenv("PATH", tmp_dir("empty_bin").c_str(), 1);
  std::string e = error_of([&] { run_capture(opt_); });
  EXPECT_CONTAINS(e, "apt-get install colmap");
  EXPECT_FALSE(fs::exists(output_ / "images")) << "it should fail before writing frames";
}

TEST_F(CaptureErrors, ColmapFailingShowsItsLog) {
  fake_colmap("echo 'fake colmap: cannot open database'\nexit 3");
  std::string e = error_of([&] { run_capture(opt_); });
  EXPECT_CONTAINS(e, "colmap features failed");
  EXPECT_CONTAINS(e, "exit status 3");
  EXPECT_CONTAINS(e, "cannot open database");
  EXPECT_TRUE(fs::exists(output_ / "colmap" / "features.log"));
}

TEST_F(CaptureErrors, NoModelMeansTooFewMatches) {
  fake_colmap("exit 0");
  EXPECT_CONTAINS(error_of([&] { run_capture(opt_); }), "too few matches");
}

TEST_F(CaptureErrors, SeveralModelsKeepTheLargest) {
  // The fake mapper "reconstructs" two models: 3 images and 9 images.
  fs::path models = tmp_dir("fake_models");
  write_colmap_model(synthetic::make_synthetic_scene(3, 20, 0).model, models / "0", true);
  write_colmap_model(synthetic::make_synthetic_scene(9, 40, 5).model, models / "1", false);
  fake_colmap(
      "if [ \"$1\" = mapper ]; then\n"
      "  while [ $# -gt 0 ]; do [ \"$1\" = --output_path ] && cp -r '" +
      models.string() + "'/. \"$2\"/; shift; done\nfi\nexit 0");
  CaptureReport r = run_capture(opt_);
  EXPECT_EQ(r.models, 2u);
  EXPECT_EQ(r.registered, 9u);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_CONTAINS(r.warnings[0], "2 disconnected models");
  EXPECT_TRUE(fs::exists(output_ / "transforms.json"));
  EXPECT_TRUE(fs::exists(output_ / "capture_report.json"));
}

TEST_F(CaptureErrors, EarlierCaptureIsReplacedOnlyWithForce) {
  // An earlier capture in the output folder: refused before any work (COLMAP is not even looked
  // for: the PATH holds none), and left as it was.
  setenv("PATH", tmp_dir("empty_bin_force").c_str(), 1);
  fs::create_directories(output_ / "images");
  std::ofstream(output_ / "capture_report.json") << "{}";
  std::ofstream(output_ / "transforms.json") << "earlier";
  std::ofstream(output_ / "images" / "old.jpg") << "old frame";
  std::string e = error_of([&] { run_capture(opt_); });
  EXPECT_CONTAINS(e, "earlier capture");
  EXPECT_CONTAINS(e, "--force");
  EXPECT_TRUE(fs::exists(output_ / "images" / "old.jpg"));
  // With force the check passes: the run goes on to look for COLMAP (and fails there).
  opt_.force = true;
  EXPECT_CONTAINS(error_of([&] { run_capture(opt_); }), "apt-get install colmap");
}

namespace {

// A COLMAP model input (sparse/0 + images/) whose model names 9 images, of which only the first
// `present` are in images/ (dummy bytes: without the head box nothing reads them).
fs::path model_input_with_images(const std::string& name, int present, double arc_rad = 1.2) {
  fs::path in = tmp_dir(name);
  synthetic::SyntheticScene s = synthetic::make_synthetic_scene(9, 300, 60, arc_rad);
  fs::create_directories(in / "sparse" / "0");
  write_colmap_model(s.model, in / "sparse" / "0", false);
  fs::create_directories(in / "images");
  int k = 0;
  for (const auto& [id, im] : s.model.images)
    if (k++ < present) std::ofstream(in / "images" / im.name) << "image " << im.name;
  return in;
}

}  // namespace

TEST_F(CaptureErrors, ModelImagesMissingFromTheFolderAreDroppedAndNamed) {
  opt_.input = model_input_with_images("model_missing_in", 5).string();
  opt_.head_box = false;
  CaptureReport r = run_capture(opt_);
  EXPECT_EQ(r.candidate_frames, 9u);
  EXPECT_EQ(r.kept_frames, 5u);
  EXPECT_EQ(r.registered, 5u);
  ASSERT_EQ(r.dropped.size(), 4u);
  EXPECT_EQ(r.dropped[0].name, "frame_1005.jpg");
  std::string all;
  for (const auto& w : r.warnings) all += w + "\n";
  EXPECT_CONTAINS(all, "4 of 9 images named by the COLMAP model");
  EXPECT_CONTAINS(all, "'frame_1005.jpg', 'frame_1006.jpg', 'frame_1007.jpg', 'frame_1008.jpg'");
  // Every frame written points at an image that is there.
  std::ifstream f(output_ / "transforms.json");
  nlohmann::json t = nlohmann::json::parse(f);
  ASSERT_EQ(t["frames"].size(), 5u);
  for (const auto& frame : t["frames"])
    EXPECT_TRUE(fs::is_regular_file(output_ / frame["file_path"].get<std::string>())) << frame["file_path"];
}

TEST_F(CaptureErrors, ModelWithTooFewImagesInTheFolderIsRefused) {
  opt_.input = model_input_with_images("model_two_in", 2).string();
  opt_.head_box = false;
  std::string e = error_of([&] { run_capture(opt_); });
  EXPECT_CONTAINS(e, "only 2 of the 9 images named by the COLMAP model");
  EXPECT_CONTAINS(e, "'frame_1002.jpg'");
  EXPECT_CONTAINS(e, "and 2 more");
  EXPECT_CONTAINS(e, "at least 3");
  EXPECT_CONTAINS(e, "put the photos the model was made from");
  EXPECT_FALSE(fs::exists(output_)) << "it should fail before writing anything";
}

TEST_F(CaptureErrors, TheReportSaysWhichYawAndPitchTheCaptureCovered) {
  // 9 cameras over +-1.2 rad (68.75 deg) of yaw, all 0.05 above the head's centre at 0.6 away
  // (pitch 4.76 deg). The box centre is the sparse points' box, within a few mm of the head's
  // centre: 1.5 deg of tolerance.
  opt_.input = model_input_with_images("coverage_wide_in", 9).string();
  opt_.head_box = false;
  CaptureReport r = run_capture(opt_);
  ASSERT_TRUE(r.coverage.has_value());
  EXPECT_NEAR(r.coverage->yaw_min, -68.75, 1.5);
  EXPECT_NEAR(r.coverage->yaw_max, 68.75, 1.5);
  EXPECT_NEAR(r.coverage->pitch_max, 4.76, 1.5);
  EXPECT_EQ(r.coverage_advice, "");
  std::ifstream f(output_ / "capture_report.json");
  nlohmann::json j = nlohmann::json::parse(f);
  EXPECT_EQ(j["coverage"]["ear_to_ear"], true);
  EXPECT_NEAR(j["coverage"]["yaw_deg"][1].get<double>(), r.coverage->yaw_max, 1e-9);
}

TEST_F(CaptureErrors, ANarrowArcWarnsToFilmFromEarToEar) {
  // +-0.35 rad = +-20 deg of yaw: the ears were never seen.
  opt_.input = model_input_with_images("coverage_narrow_in", 9, 0.35).string();
  opt_.head_box = false;
  CaptureReport r = run_capture(opt_);
  ASSERT_TRUE(r.coverage.has_value());
  EXPECT_NEAR(r.coverage->yaw_max - r.coverage->yaw_min, 40.1, 3.0);
  EXPECT_CONTAINS(r.coverage_advice, "Film from ear to ear");
  std::string all;
  for (const auto& w : r.warnings) all += w + "\n";
  EXPECT_CONTAINS(all, "Film from ear to ear");
  std::ifstream f(output_ / "capture_report.json");
  nlohmann::json j = nlohmann::json::parse(f);
  EXPECT_EQ(j["coverage"]["ear_to_ear"], false);
  EXPECT_CONTAINS(j["coverage"]["advice"].get<std::string>(), "turn the head");
}
