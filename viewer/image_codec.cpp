// sRGB conversion, JPEG (libjpeg-turbo) and PNG (OpenCV) encoding of viewer frames (image_codec.h).
#include "viewer/image_codec.h"

#include <spdlog/spdlog.h>
#include <turbojpeg.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

namespace lorgnette::viewer {
namespace {

// 4096 steps over [0, 1] in linear light: below one 8-bit sRGB step everywhere except the darkest
// values, where the table is finer than the sRGB curve's slope needs anyway.
const std::array<uint8_t, 4097>& srgb_table() {
  static const std::array<uint8_t, 4097> table = [] {
    std::array<uint8_t, 4097> t{};
    for (int i = 0; i <= 4096; ++i) t[i] = uint8_t(std::lround(255.0f * linear_to_srgb(float(i) / 4096.0f)));
    return t;
  }();
  return table;
}

}  // namespace

Rgb8 to_srgb8(const Image& linear) {
  if (linear.channels < 3) throw std::invalid_argument("to_srgb8 needs an RGB or RGBA image");
  const auto& lut = srgb_table();
  Rgb8 out;
  out.width = linear.width, out.height = linear.height;
  const size_t n = size_t(linear.width) * linear.height;
  out.pixels.resize(n * 3);
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      float v = linear.pixels[i * linear.channels + c];
      int k = std::isnan(v) ? 0 : int(std::clamp(v, 0.0f, 1.0f) * 4096.0f + 0.5f);
      out.pixels[i * 3 + c] = lut[k];
    }
  return out;
}

void paste_rows(Rgb8& dst, const Rgb8& band, int y0) {
  if (band.width != dst.width || y0 < 0 || y0 + band.height > dst.height)
    throw std::invalid_argument("paste_rows: the band does not fit the image");
  std::memcpy(dst.pixels.data() + size_t(y0) * dst.width * 3, band.pixels.data(), band.pixels.size());
}

JpegEncoder::JpegEncoder() : handle_(tjInitCompress()) {
  if (!handle_)
    throw std::runtime_error(std::string("libjpeg-turbo: cannot create a compressor: ") + tjGetErrorStr());
}

JpegEncoder::~JpegEncoder() {
  if (handle_ && tjDestroy(static_cast<tjhandle>(handle_)) != 0)
    spdlog::warn("libjpeg-turbo: tjDestroy failed");
}

std::vector<uint8_t> JpegEncoder::encode(const Rgb8& image, int quality) {
  unsigned char* buf = nullptr;
  unsigned long size = 0;
  int rc = tjCompress2(static_cast<tjhandle>(handle_), image.pixels.data(), image.width, 0, image.height,
                       TJPF_RGB, &buf, &size, TJSAMP_420, std::clamp(quality, 1, 100), TJFLAG_FASTDCT);
  if (rc != 0) {
    std::string msg = tjGetErrorStr2(static_cast<tjhandle>(handle_));
    tjFree(buf);
    throw std::runtime_error("JPEG encoding failed (libjpeg-turbo): " + msg);
  }
  std::vector<uint8_t> out(buf, buf + size);
  tjFree(buf);
  return out;
}

std::vector<uint8_t> encode_png(const Rgb8& image) {
  cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<uint8_t*>(image.pixels.data())), bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  std::vector<uint8_t> out;
  if (!cv::imencode(".png", bgr, out)) throw std::runtime_error("PNG encoding failed (OpenCV)");
  return out;
}

}  // namespace lorgnette::viewer
