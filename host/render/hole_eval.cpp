// Holes in a render's head interior; see hole_eval.h.
#include "host/render/hole_eval.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace lorgnette::render {

std::vector<uint8_t> head_interior_mask(const Image& matte, const HoleEvalOptions& o) {
  const int w = matte.width, h = matte.height;
  std::vector<uint8_t> mask(size_t(w) * size_t(h), 0);
  cv::Mat inside(h, w, CV_8U, cv::Scalar(0));
  int top = h, bottom = -1;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (matte.at(x, y, 0) >= 0.5f) {
        inside.at<uint8_t>(y, x) = 255;
        top = std::min(top, y), bottom = std::max(bottom, y);
      }
  if (bottom < 0) return mask;
  cv::Mat interior;
  const int k = 2 * o.erode_px + 1;
  cv::erode(inside, interior, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(k, k)));
  const int last = top + int(o.upper_share * double(bottom - top + 1)) - 1;
  for (int y = top; y <= std::min(last, h - 1); ++y)
    for (int x = 0; x < w; ++x) mask[size_t(y) * w + x] = interior.at<uint8_t>(y, x) ? 1 : 0;
  return mask;
}

InteriorHoles head_interior_holes(const Image& pred, const Image& matte, const HoleEvalOptions& o) {
  const int w = matte.width, h = matte.height;
  if (pred.width != w || pred.height != h || pred.channels != 4)
    throw std::runtime_error("head_interior_holes: the prediction must be RGBA of the matte's size");
  const std::vector<uint8_t> interior = head_interior_mask(matte, o);
  InteriorHoles r;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!interior[size_t(y) * w + x]) continue;
      ++r.interior_pixels;
      r.holes += pred.at(x, y, 3) < o.opacity_below;
    }
  r.share = r.interior_pixels ? double(r.holes) / double(r.interior_pixels) : 0.0;
  return r;
}

}  // namespace lorgnette::render
