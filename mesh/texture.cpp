// Bilinear texture sampling, in-memory image decoding (OpenCV) and downsampling; see texture.h.
#include "mesh/texture.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

namespace lorgnette::mesh {
namespace {

int wrap(int i, int n) {
  int r = i % n;
  return r < 0 ? r + n : r;
}

Eigen::Vector4f texel(const Image& im, int x, int y) {
  x = wrap(x, im.width);
  y = wrap(y, im.height);
  const float* p = &im.pixels[(static_cast<size_t>(y) * im.width + x) * im.channels];
  switch (im.channels) {
    case 1:
      return {p[0], p[0], p[0], 1.0f};
    case 2:
      return {p[0], p[0], p[0], p[1]};
    case 3:
      return {p[0], p[1], p[2], 1.0f};
    default:
      return {p[0], p[1], p[2], p[3]};
  }
}

}  // namespace

Eigen::Vector4f sample_texture(const Image& image, const Eigen::Vector2f& uv) {
  if (image.empty()) return Eigen::Vector4f::Ones();
  float x = uv.x() * image.width - 0.5f, y = uv.y() * image.height - 0.5f;
  if (!std::isfinite(x) || !std::isfinite(y)) return texel(image, 0, 0);
  float fx = std::floor(x), fy = std::floor(y);
  float ax = x - fx, ay = y - fy;
  int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
  return (1 - ay) * ((1 - ax) * texel(image, x0, y0) + ax * texel(image, x0 + 1, y0)) +
         ay * ((1 - ax) * texel(image, x0, y0 + 1) + ax * texel(image, x0 + 1, y0 + 1));
}

Image decode_image_bytes(const unsigned char* data, size_t size, const std::string& what) {
  if (data == nullptr || size == 0) throw std::runtime_error(fmt::format("{}: empty image data", what));
  cv::Mat raw(1, static_cast<int>(size), CV_8UC1, const_cast<unsigned char*>(data));
  cv::Mat m = cv::imdecode(raw, cv::IMREAD_UNCHANGED);
  if (m.empty())
    throw std::runtime_error(fmt::format("{}: embedded texture is not a decodable PNG/JPEG", what));
  int c = m.channels();
  double scale = m.depth() == CV_16U ? 1.0 / 65535.0 : 1.0 / 255.0;
  cv::Mat f;
  m.convertTo(f, CV_32F, scale);
  Image im(f.cols, f.rows, c);
  for (int y = 0; y < f.rows; ++y) {
    const float* row = f.ptr<float>(y);
    for (int x = 0; x < f.cols; ++x) {
      for (int k = 0; k < c; ++k) {
        // OpenCV stores BGR(A); swap to RGB(A).
        int src = (c >= 3 && k < 3) ? 2 - k : k;
        float v = row[x * c + src];
        bool colour = (c >= 3) ? k < 3 : k < 1;
        im.at(x, y, k) = colour ? srgb_to_linear(v) : v;
      }
    }
  }
  return im;
}

Image downsample_to(const Image& image, int max_side) {
  Image cur = image;
  while (max_side > 0 && std::max(cur.width, cur.height) > max_side && cur.width > 1 && cur.height > 1) {
    Image half(cur.width / 2, cur.height / 2, cur.channels);
    for (int y = 0; y < half.height; ++y)
      for (int x = 0; x < half.width; ++x)
        for (int k = 0; k < cur.channels; ++k)
          half.at(x, y, k) = 0.25f * (cur.at(2 * x, 2 * y, k) + cur.at(2 * x + 1, 2 * y, k) +
                                      cur.at(2 * x, 2 * y + 1, k) + cur.at(2 * x + 1, 2 * y + 1, k));
    cur = std::move(half);
  }
  return cur;
}

}  // namespace lorgnette::mesh
