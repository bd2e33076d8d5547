// Detector noise for stability studies (see landmark_noise.h).
#include "eval/landmark_noise.h"

#include <memory>
#include <mutex>
#include <random>

namespace lorgnette::fit {

DetectFn with_landmark_noise(DetectFn inner, double sigma_px, unsigned seed) {
  struct Draws {
    std::mutex mutex;
    std::mt19937 rng;
    std::normal_distribution<double> noise{0.0, 1.0};
  };
  auto draws = std::make_shared<Draws>();
  draws->rng.seed(seed);
  return [inner = std::move(inner), draws, sigma_px](const std::vector<unsigned char>& srgb, int width,
                                                     int height, double face_px) {
    FaceDetection d = inner(srgb, width, height, face_px);
    std::lock_guard<std::mutex> lock(draws->mutex);
    for (auto& p : d.points)
      p += sigma_px * Eigen::Vector2d(draws->noise(draws->rng), draws->noise(draws->rng));
    return d;
  };
}

DetectFn noisy_dlib_detector(const DetectorOptions& options, double sigma_px, unsigned seed) {
  auto dlib = std::make_shared<LandmarkDetector>(options);
  DetectFn plain = [dlib](const std::vector<unsigned char>& srgb, int width, int height, double face_px) {
    return dlib->detect_srgb8(srgb.data(), width, height, face_px);
  };
  return with_landmark_noise(std::move(plain), sigma_px, seed);
}

}  // namespace lorgnette::fit
