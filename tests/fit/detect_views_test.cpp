// detect_views tests on a mesh ViewSource of the Lee Perry-Smith head scan: detecting on a worker
// thread while the next view renders gives exactly the serial results (also with a study's detector
// noise, eval/landmark_noise.h, whose draws must keep their order); running dlib's HOG stage on a shrunk copy
// (the framing hint) gives exactly the full-resolution boxes and landmarks; bad options are clear errors.
#include "fit/detect_views.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "eval/landmark_noise.h"
#include "eval/mesh_view_source.h"
#include "fit/camera_math.h"
#include "fit/fit.h"

namespace lorgnette::fit {
namespace {

const std::string kHead = std::string(LORGNETTE_DATA_DIR) + "/heads/lee-perry-smith/LeePerrySmith.glb";

class DetectViews : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!std::filesystem::exists(kHead) || !std::filesystem::exists(DetectorOptions{}.model_path)) return;
    source_ = MeshViewSource::load(kHead).release();
  }
  static void TearDownTestSuite() {
    delete source_;
    source_ = nullptr;
  }
  void SetUp() override {
    if (!source_) GTEST_SKIP() << "needs " << kHead << " and the dlib model (Debian package libdlib-data)";
  }
  // Five views on a cap framed on the scan's face (about 0.43 of the 320 px view width).
  static std::vector<Camera> cameras(FitOptions& opt) {
    Orbit o;
    o.target = source_->bounds().center().cast<double>() + Eigen::Vector3d(0, 2.0, 0);
    o.distance = 14.0;
    o.fov_y_deg = 25.0;
    o.width = o.height = opt.front.width = opt.front.height = 320;
    opt.front.face_fraction = 0.43;
    std::vector<Camera> cams;
    for (double yaw : {-20.0, -10.0, 0.0, 10.0, 20.0}) cams.push_back(orbit_camera(o, yaw, 5.0));
    return cams;
  }
  static MeshViewSource* source_;
};
MeshViewSource* DetectViews::source_ = nullptr;

void expect_identical(const std::vector<ViewRecord>& a, const std::vector<ViewRecord>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].detection.found, b[i].detection.found);
    EXPECT_EQ(a[i].detection.box, b[i].detection.box);
    ASSERT_EQ(a[i].detection.points.size(), b[i].detection.points.size());
    for (size_t k = 0; k < a[i].detection.points.size(); ++k)
      EXPECT_EQ(a[i].detection.points[k], b[i].detection.points[k]);
  }
}

TEST_F(DetectViews, OverlappedDetectionEqualsSerial) {
  FitOptions opt;
  std::vector<Camera> cams = cameras(opt);
  // Each run with its own noisy detector of the same seed: the noise draws must stay in view order.
  LandmarkDetector serial_det(noisy_dlib_detector(opt.detection.detector, 1.5, 1));
  LandmarkDetector overlapped_det(noisy_dlib_detector(opt.detection.detector, 1.5, 1));
  opt.detection.detector.overlap_render = false;
  std::vector<ViewRecord> serial = detect_views(*source_, serial_det, cams, view_detect_options(opt));
  opt.detection.detector.overlap_render = true;
  std::vector<ViewRecord> overlapped = detect_views(*source_, overlapped_det, cams, view_detect_options(opt));
  for (const auto& v : serial) EXPECT_TRUE(v.detection.found);
  expect_identical(serial, overlapped);
}

TEST_F(DetectViews, ShrunkHogGivesTheFullResolutionResult) {
  FitOptions opt;
  std::vector<Camera> cams = cameras(opt);
  DetectorOptions full_opt;
  full_opt.hog_face_px = 0.0;  // the HOG stage at full resolution
  LandmarkDetector full(full_opt);
  DetectorOptions hinted_opt;
  hinted_opt.hog_face_px = 100.0;  // 138 px faces: one pyramid step skipped
  LandmarkDetector hinted(hinted_opt);
  std::vector<ViewRecord> a = detect_views(*source_, full, cams, view_detect_options(opt));
  opt.detection.detector.overlap_render = true;
  std::vector<ViewRecord> b = detect_views(*source_, hinted, cams, view_detect_options(opt));
  for (const auto& v : b) EXPECT_TRUE(v.detection.found);
  // Exact: the shrink is the detector's own pyramid step and boxes are mapped back as dlib does.
  expect_identical(a, b);
}

TEST_F(DetectViews, CroppedRenderIsTheFullRenderInsideAndWhiteOutside) {
  FitOptions opt;
  const Camera cam = cameras(opt)[1];
  Image full = source_->render(cam);
  Image crop = render_cropped(*source_, cam, 0.75);  // 240 x 240 of 320 x 320, from (40, 40)
  ASSERT_EQ(crop.width, full.width);
  ASSERT_EQ(crop.height, full.height);
  ASSERT_EQ(crop.channels, full.channels);
  int inside = 0, outside = 0;
  for (int y = 0; y < full.height; ++y)
    for (int x = 0; x < full.width; ++x)
      for (int c = 0; c < full.channels; ++c) {
        const bool in = x >= 40 && x < 280 && y >= 40 && y < 280;
        // Exact: the sub-camera's rays are the full camera's (integer principal-point shift).
        if (in)
          inside += crop.at(x, y, c) == full.at(x, y, c);
        else
          outside += crop.at(x, y, c) == 1.0f;
      }
  EXPECT_EQ(inside, 240 * 240 * full.channels);
  EXPECT_EQ(outside, (320 * 320 - 240 * 240) * full.channels);
  Camera distorted = cam;
  distorted.k1 = 0.1f;
  EXPECT_THROW(render_cropped(*source_, distorted, 0.75), std::runtime_error);
}

TEST_F(DetectViews, CroppedViewsGiveTheFullViewDetections) {
  FitOptions opt;
  std::vector<Camera> cams = cameras(opt);
  LandmarkDetector det(opt.detection.detector);
  opt.detection.detector.render_crop = 0.0;
  std::vector<ViewRecord> full = detect_views(*source_, det, cams, view_detect_options(opt));
  opt.detection.detector.render_crop = 0.75;  // the default: the face (0.43 of the width) with a margin
  std::vector<ViewRecord> cropped = detect_views(*source_, det, cams, view_detect_options(opt));
  expect_identical(full, cropped);
}

TEST(DetectorOptionsCheck, TooSmallHogFaceIsAClearError) {
  if (!std::filesystem::exists(DetectorOptions{}.model_path)) GTEST_SKIP() << "needs libdlib-data";
  DetectorOptions o;
  o.hog_face_px = 40.0;
  try {
    LandmarkDetector d(o);
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("hog_face_px"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace lorgnette::fit
