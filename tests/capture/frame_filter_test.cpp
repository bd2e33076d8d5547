// Frame filters on frames made in the test: blurred frames among sharp ones are dropped with a
// reason, an evenly blurred capture is kept with a warning; the eye aspect ratio of synthetic eye
// landmarks, the blink decision (closed frames dropped, a closed-eyed capture kept with a warning,
// faceless frames kept), and dlib's landmarks on a real open-eyed frame of the in2n-face capture.
#include "capture/frame_filter.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "capture/capture.h"
#include "capture/eye_openness.h"

namespace fs = std::filesystem;
using namespace lorgnette::capture;

namespace {

// A textured frame (uniform noise, softened a little like a real photo), optionally defocused.
cv::Mat textured_frame(int seed, double defocus_sigma) {
  cv::Mat img(120, 160, CV_8UC3);
  cv::RNG rng(seed);
  rng.fill(img, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(img, img, cv::Size(0, 0), 0.8);
  if (defocus_sigma > 0) cv::GaussianBlur(img, img, cv::Size(0, 0), defocus_sigma);
  return img;
}

std::array<Eigen::Vector2d, 6> eye(double half_height) {
  return {Eigen::Vector2d(0, 0),  Eigen::Vector2d(10, -half_height), Eigen::Vector2d(20, -half_height),
          Eigen::Vector2d(30, 0), Eigen::Vector2d(20, half_height),  Eigen::Vector2d(10, half_height)};
}

}  // namespace

TEST(BlurFilter, DropsDefocusedFramesAmongSharpOnes) {
  FrameSet set;
  for (int i = 0; i < 10; ++i) {
    set.images.push_back(textured_frame(100 + i, i == 3 || i == 7 ? 2.5 : 0.0));
    set.names.push_back("f" + std::to_string(i) + ".jpg");
  }
  CaptureOptions opt;
  opt.blink_filter = false;
  CaptureReport report;
  auto kept = select_frames(set, opt, report);
  EXPECT_EQ(kept, (std::vector<size_t>{0, 1, 2, 4, 5, 6, 8, 9}));
  ASSERT_EQ(report.dropped.size(), 2u);
  EXPECT_EQ(report.dropped[0].name, "f3.jpg");
  EXPECT_NE(report.dropped[0].reason.find("blurred"), std::string::npos);
  EXPECT_TRUE(report.warnings.empty());
}

TEST(BlurFilter, KeepsAnEvenlyBlurredCaptureAndWarns) {
  std::vector<double> sharpness;
  for (int i = 0; i < 8; ++i) sharpness.push_back(laplacian_variance(textured_frame(200 + i, 6.0)));
  FilterDecision d = blur_filter(sharpness);
  EXPECT_EQ(d.dropped(), 0u);
  ASSERT_EQ(d.warnings.size(), 1u);
  EXPECT_NE(d.warnings[0].find("blurred"), std::string::npos);
}

TEST(BlurFilter, NeverDropsEveryFrame) {
  FilterDecision d = blur_filter({5.0, 5.0, 5.0});
  EXPECT_EQ(d.dropped(), 0u);
  EXPECT_TRUE(blur_filter({}).keep.empty());
}

TEST(BlinkFilter, EyeAspectRatioOfSyntheticEyes) {
  EXPECT_NEAR(eye_aspect_ratio(eye(5.0)), 20.0 / 60.0, 1e-12);
  EXPECT_NEAR(eye_aspect_ratio(eye(1.0)), 4.0 / 60.0, 1e-12);
}

TEST(BlinkFilter, DropsClosedFramesKeepsFacelessOnes) {
  std::vector<std::optional<double>> ear = {0.30, 0.31,         0.29, eye_aspect_ratio(eye(1.0)),
                                            0.30, std::nullopt, 0.32};
  FilterDecision d = blink_filter(ear);
  EXPECT_EQ(d.keep, (std::vector<bool>{true, true, true, false, true, true, true}));
  EXPECT_NE(d.reasons[3].find("eyes closed"), std::string::npos);
  EXPECT_TRUE(d.warnings.empty());
}

TEST(BlinkFilter, KeepsACapturewithClosedEyesThroughoutAndWarns) {
  FilterDecision d = blink_filter({0.07, 0.08, 0.06, 0.07, 0.075});
  EXPECT_EQ(d.dropped(), 0u);
  ASSERT_FALSE(d.warnings.empty());
  EXPECT_NE(d.warnings[0].find("closed"), std::string::npos);
}

TEST(BlinkFilter, DlibFindsOpenEyesOnARealFrame) {
  fs::path frame = fs::path(LORGNETTE_DATA_DIR) / "heads/in2n-face/images/frame_00033.jpg";
  const char* model = "/usr/share/dlib/shape_predictor_68_face_landmarks.dat";
  if (!fs::exists(frame) || !fs::exists(model)) GTEST_SKIP() << "needs " << frame << " and " << model;
  EyeOpenness eyes(model);
  auto ear = eyes.measure(cv::imread(frame.string()));
  ASSERT_TRUE(ear.has_value()) << "no face found in " << frame;
  // Open eyes measure 0.2-0.4 in the EAR literature (Soukupova & Cech 2016).
  EXPECT_GT(*ear, 0.2);
  EXPECT_LT(*ear, 0.45);
  EXPECT_FALSE(eyes.measure(textured_frame(7, 0.0)).has_value());
}
