// EyeOpenness: OpenCV frame -> linear Image -> fit::LandmarkDetector -> eye aspect ratio.
#include "capture/eye_openness.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "capture/frame_filter.h"
#include "fit/landmarks_dlib.h"
#include "host/util/image_io.h"

namespace lorgnette::capture {
namespace {

Image to_linear_image(const cv::Mat& bgr) {
  static const std::vector<float> lut = [] {
    std::vector<float> t(256);
    for (int i = 0; i < 256; ++i) t[i] = srgb_to_linear(i / 255.0f);
    return t;
  }();
  Image img(bgr.cols, bgr.rows, 3);
  for (int y = 0; y < bgr.rows; ++y) {
    const auto* row = bgr.ptr<cv::Vec3b>(y);
    for (int x = 0; x < bgr.cols; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = lut[row[x][2 - c]];
  }
  return img;
}

}  // namespace

EyeOpenness::EyeOpenness(const std::string& model_path, int max_side) : max_side_(max_side) {
  fit::DetectorOptions opt;
  opt.model_path = model_path;
  detector_ = std::make_unique<fit::LandmarkDetector>(opt);
}

EyeOpenness::~EyeOpenness() = default;

std::optional<double> EyeOpenness::measure(const cv::Mat& bgr) const {
  cv::Mat small = bgr;
  int side = std::max(bgr.cols, bgr.rows);
  if (side > max_side_) {
    double s = static_cast<double>(max_side_) / side;
    cv::resize(bgr, small, cv::Size(), s, s, cv::INTER_AREA);
  }
  fit::FaceDetection det = detector_->detect(to_linear_image(small));
  if (!det.found || det.points.size() != 68) return std::nullopt;
  std::array<Eigen::Vector2d, 6> right, left;
  for (int k = 0; k < 6; ++k) {
    right[k] = det.points[36 + k];
    left[k] = det.points[42 + k];
  }
  return 0.5 * (eye_aspect_ratio(right) + eye_aspect_ratio(left));
}

}  // namespace lorgnette::capture
