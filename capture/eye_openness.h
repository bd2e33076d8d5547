// Eye openness of a frame for the blink filter: the mean eye aspect ratio of both eyes from the
// 68-point landmarks of fit/landmarks_dlib.h (dlib HOG detector + iBUG shape predictor), measured
// on a downscaled copy (faces in head captures are large; EAR does not depend on scale).
#pragma once
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

namespace lorgnette::fit {
class LandmarkDetector;
}

namespace lorgnette::capture {

class EyeOpenness {
 public:
  // Loads dlib's shape predictor (throws naming the file and Debian's libdlib-data when missing).
  explicit EyeOpenness(
      const std::string& model_path = "/usr/share/dlib/shape_predictor_68_face_landmarks.dat",
      int max_side = 480);
  ~EyeOpenness();
  EyeOpenness(const EyeOpenness&) = delete;
  EyeOpenness& operator=(const EyeOpenness&) = delete;

  // 8-bit BGR frame -> mean eye aspect ratio, or nullopt when no face is found.
  std::optional<double> measure(const cv::Mat& bgr) const;

 private:
  std::unique_ptr<fit::LandmarkDetector> detector_;
  int max_side_;
};

}  // namespace lorgnette::capture
