// The 2D landmark detector: dlib's HOG frontal face detector and its 68-point shape predictor
// (iBUG 300-W model from Debian's libdlib-data; it restricts commercial use). dlib stays inside
// landmarks_dlib.cpp (its headers compile slowly); this header is plain Eigen.
#pragma once
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "host/util/image_io.h"

namespace lorgnette::fit {

struct DetectorOptions {
  std::string model_path = "/usr/share/dlib/shape_predictor_68_face_landmarks.dat";
  int upsample = 0;  // pyramid up-sampling steps for small faces (each doubles the pixels per side)
  // When the caller knows how wide the face is (framed views), the HOG face detector (the costly
  // part: a sliding window over an image pyramid) runs on a copy shrunk so the face is about this
  // many pixels wide; its box is mapped back and the shape predictor always sees the full image.
  // 0 = always full resolution. dlib's window is 80x80 px: keep this well above 80.
  double hog_face_px = 100.0;
  // detect_views (fit.h): detect view i on a worker thread while view i + 1 renders. Results are
  // identical; the gain is small because detection is ~2 % of a view's time on a NeRF.
  bool overlap_render = true;
  // detect_views: render only the central `render_crop` x `render_crop` part of each framed view
  // (the face sits in the middle, FitOptions::front.face_fraction wide) and fill the rest with white, the
  // fit's background; pixels inside are those of the full render. A view whose face is missing or
  // comes within 8 px of the crop's edge is rendered again in full. 0 = render the whole view.
  double render_crop = 0.75;  // identical fits to 0 on the scan and demo NeRFs; 0.65 was not
};

struct FaceDetection {
  bool found = false;
  int faces = 0;                                  // faces the detector saw (the largest is used)
  Eigen::Vector4d box = Eigen::Vector4d::Zero();  // left, top, right, bottom (pixels)
  double score = 0.0;                             // detector confidence of the chosen face
  std::vector<Eigen::Vector2d> points;            // 68 landmarks, continuous pixel coordinates
};

// A detector supplied by the caller instead of dlib (the Python bindings: MediaPipe, a licensed
// model): `srgb` is the interleaved 8-bit sRGB RGB image dlib would see (width x height x 3, alpha
// composited over white), `face_px` the face's expected width in pixels (0 = unknown). A detection
// with `found` must carry the 68 points in iBUG order (continuous pixel coordinates).
using DetectFn = std::function<FaceDetection(const std::vector<unsigned char>& srgb, int width, int height,
                                             double face_px)>;

class LandmarkDetector {
 public:
  // Loads the shape predictor; throws naming the path and the Debian package when missing.
  explicit LandmarkDetector(const DetectorOptions& opt = {});
  // Runs `fn` instead of dlib (no model is loaded); detect() converts each view as it would for dlib.
  explicit LandmarkDetector(DetectFn fn);
  ~LandmarkDetector();
  LandmarkDetector(const LandmarkDetector&) = delete;
  LandmarkDetector& operator=(const LandmarkDetector&) = delete;

  // Linear RGB(A) image -> 8-bit sRGB -> detector. `face_px`: the face's expected width in pixels
  // when known (0 = unknown), used with DetectorOptions::hog_face_px. Thread-compatible, not
  // thread-safe (one call at a time per detector).
  FaceDetection detect(const Image& linear_rgb, double face_px = 0.0) const;
  // The dlib stage of detect() on an 8-bit sRGB RGB image (width x height x 3); throws for a
  // detector made from a DetectFn.
  FaceDetection detect_srgb8(const unsigned char* rgb, int width, int height, double face_px = 0.0) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  DetectFn fn_;
};

// Converts a linear float image to interleaved 8-bit sRGB RGB (alpha composited over `background`).
std::vector<unsigned char> to_srgb8(const Image& linear, float background = 1.0f);

}  // namespace lorgnette::fit
