// The 2D landmark detector: dlib's HOG frontal face detector and its 68-point shape predictor
// (iBUG 300-W model from Debian's libdlib-data; it restricts commercial use). dlib stays inside
// landmarks_dlib.cpp (its headers compile slowly); this header is plain Eigen.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "host/util/image_io.h"

namespace lorgnette::fit {

struct DetectorOptions {
  std::string model_path = "/usr/share/dlib/shape_predictor_68_face_landmarks.dat";
  int upsample = 0;  // pyramid up-sampling steps for small faces (each doubles the pixels per side)
};

struct FaceDetection {
  bool found = false;
  int faces = 0;                             // faces the detector saw (the largest is used)
  Eigen::Vector4d box = Eigen::Vector4d::Zero();  // left, top, right, bottom (pixels)
  double score = 0.0;                        // detector confidence of the chosen face
  std::vector<Eigen::Vector2d> points;       // 68 landmarks, continuous pixel coordinates
};

class LandmarkDetector {
 public:
  // Loads the shape predictor; throws naming the path and the Debian package when missing.
  explicit LandmarkDetector(const DetectorOptions& opt = {});
  ~LandmarkDetector();
  LandmarkDetector(const LandmarkDetector&) = delete;
  LandmarkDetector& operator=(const LandmarkDetector&) = delete;

  // Linear RGB(A) image -> 8-bit sRGB -> detector. Thread-compatible, not thread-safe.
  FaceDetection detect(const Image& linear_rgb) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Converts a linear float image to interleaved 8-bit sRGB RGB (alpha composited over `background`).
std::vector<unsigned char> to_srgb8(const Image& linear, float background = 1.0f);

}  // namespace lorgnette::fit
