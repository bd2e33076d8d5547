// The evaluation error image: prediction | truth | heat map of the mean absolute sRGB error, using
// OpenCV's INFERNO colour map (perceptually ordered, readable in greyscale print).
#include <fmt/format.h>

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "host/dataset/media.h"
#include "host/dataset/metrics.h"

namespace lorgnette::dataset {

Image make_error_image(const Image& prediction, const Image& truth, const ErrorImageOptions& options) {
  if (prediction.width != truth.width || prediction.height != truth.height)
    throw std::runtime_error(fmt::format("error image: prediction is {}x{} but truth is {}x{}",
                                         prediction.width, prediction.height, truth.width, truth.height));
  if (!(options.max_error > 0)) throw std::runtime_error("error image: max_error must be > 0");
  Image pred = composite_over(prediction, options.background);
  Image ref = composite_over(truth, options.background);
  int w = truth.width, h = truth.height;
  cv::Mat level(h, w, CV_8UC1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float e = 0;
      for (int c = 0; c < 3; ++c)
        e += std::abs(linear_to_srgb(pred.at(x, y, c)) - linear_to_srgb(ref.at(x, y, c)));
      level.at<uint8_t>(y, x) =
          static_cast<uint8_t>(std::clamp(e / 3.0f / options.max_error, 0.0f, 1.0f) * 255.0f + 0.5f);
    }
  cv::Mat heat;
  cv::applyColorMap(level, heat, cv::COLORMAP_INFERNO);  // 8-bit BGR, sRGB-encoded
  Image out(3 * w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        out.at(x, y, c) = pred.at(x, y, c);
        out.at(w + x, y, c) = ref.at(x, y, c);
        out.at(2 * w + x, y, c) = srgb_to_linear(heat.at<cv::Vec3b>(y, x)[2 - c] / 255.0f);
      }
  return out;
}

}  // namespace lorgnette::dataset
