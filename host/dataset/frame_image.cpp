// Frame image reading and downscaling for the dataset loader; see frame_image.h.
#include "host/dataset/frame_image.h"

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace lorgnette::dataset::detail {

ImageHeader read_image_header(const std::string& path) {
  if (!std::filesystem::is_regular_file(path))
    throw std::runtime_error(fmt::format("image '{}' does not exist", path));
  auto in = OIIO::ImageInput::open(path);
  if (!in)
    throw std::runtime_error(
        fmt::format("cannot read image '{}': {} (is it a valid PNG/JPEG/EXR?)", path, OIIO::geterror()));
  const OIIO::ImageSpec& spec = in->spec();
  ImageHeader h{spec.width, spec.height, spec.nchannels, spec.alpha_channel >= 0 || spec.nchannels == 4};
  in->close();
  if (h.width <= 0 || h.height <= 0 || h.channels <= 0)
    throw std::runtime_error(fmt::format("image '{}' has no pixels", path));
  return h;
}

namespace {

// 8-bit files: decode as bytes and map through a 256-entry table built with srgb_to_linear, giving
// bitwise the values of image_io's read_image (a test checks it) about 3x faster on 2-megapixel
// photos than a pow per sample. Returns an empty Image for other formats (the caller falls back);
// throws when the file is one of them but does not decode cleanly (see image_io's read_image).
Image read_rgba8(const std::string& path, bool* had_alpha) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) return {};
  const OIIO::ImageSpec& spec = in->spec();
  int nc = spec.nchannels;
  if (spec.format.basetype != OIIO::TypeDesc::UINT8 || nc < 1 || nc > 4 ||
      (nc == 3 && spec.alpha_channel >= 0) || (nc == 4 && spec.alpha_channel != 3) || spec.width <= 0 ||
      spec.height <= 0)
    return {};
  std::vector<uint8_t> bytes(static_cast<size_t>(spec.width) * spec.height * nc);
  bool ok = in->read_image(0, 0, 0, nc, OIIO::TypeDesc::UINT8, bytes.data());
  if (!ok || in->has_error())
    throw std::runtime_error(
        fmt::format("image '{}' is corrupt or truncated: {}", path, decode_error_text(in->geterror())));
  // Byte -> float exactly as OIIO converts it (its scale differs from v / 255.0f by an ulp).
  static const std::vector<float> unit = [] {
    std::vector<uint8_t> v(256);
    for (int i = 0; i < 256; ++i) v[i] = static_cast<uint8_t>(i);
    std::vector<float> t(256);
    OIIO::convert_pixel_values(OIIO::TypeDesc::UINT8, v.data(), OIIO::TypeDesc::FLOAT, t.data(), 256);
    return t;
  }();
  static const std::vector<float> lut = [] {
    std::vector<float> t(256);
    for (int v = 0; v < 256; ++v) t[v] = srgb_to_linear(unit[v]);
    return t;
  }();
  Image out(spec.width, spec.height, 4, 1.0f);
  bool alpha = nc == 2 || nc == 4;
  size_t n = static_cast<size_t>(spec.width) * spec.height;
  for (size_t p = 0; p < n; ++p) {
    const uint8_t* s = &bytes[p * nc];
    float* d = &out.pixels[p * 4];
    if (nc <= 2) {
      d[0] = d[1] = d[2] = lut[s[0]];
    } else {
      d[0] = lut[s[0]];
      d[1] = lut[s[1]];
      d[2] = lut[s[2]];
    }
    if (alpha) d[3] = unit[s[nc - 1]];
  }
  *had_alpha = alpha;
  return out;
}

}  // namespace

Image read_rgba(const std::string& path, bool* had_alpha) {
  if (Image fast = read_rgba8(path, had_alpha); !fast.empty()) return fast;
  Image src = read_image(path);
  *had_alpha = src.channels == 2 || src.channels == 4;
  if (src.channels == 4) return src;
  Image out(src.width, src.height, 4, 1.0f);
  size_t n = static_cast<size_t>(src.width) * src.height;
  for (size_t p = 0; p < n; ++p) {
    const float* s = &src.pixels[p * src.channels];
    float* d = &out.pixels[p * 4];
    switch (src.channels) {
      case 1:
        d[0] = d[1] = d[2] = s[0];
        break;
      case 2:
        d[0] = d[1] = d[2] = s[0];
        d[3] = s[1];
        break;
      default:
        d[0] = s[0];
        d[1] = s[1];
        d[2] = s[2];
        break;  // 3 or > 4: extra channels dropped
    }
  }
  return out;
}

Image read_mask(const std::string& path) {
  ImageHeader h = read_image_header(path);  // throws for a missing or unreadable file
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw std::runtime_error(fmt::format("cannot read mask '{}': {}", path, OIIO::geterror()));
  Image m(h.width, h.height, 1);
  // Channel 0 only, as stored (no colour conversion: a mask is coverage, not a colour).
  bool ok = in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, m.pixels.data());
  if (!ok || in->has_error())
    throw std::runtime_error(
        fmt::format("mask '{}' is corrupt or truncated: {}", path, decode_error_text(in->geterror())));
  float hi = 0.0f;
  for (float& v : m.pixels) {
    if (!std::isfinite(v)) v = 0.0f;
    v = std::clamp(v, 0.0f, 1.0f);
    hi = std::max(hi, v);
  }
  if (hi > 0.0f && hi <= 1.5f / 255.0f)  // a 0/1 mask stored in 8 bits
    for (float& v : m.pixels) v = v > 0.0f ? 1.0f : 0.0f;
  return m;
}

void scaled_size(int w, int h, int downscale, int max_side, int* out_w, int* out_h) {
  double s = 1.0 / std::max(1, downscale);
  if (max_side > 0 && std::max(w, h) * s > max_side) s = static_cast<double>(max_side) / std::max(w, h);
  *out_w = std::max(1, static_cast<int>(std::lround(w * s)));
  *out_h = std::max(1, static_cast<int>(std::lround(h * s)));
}

Image resize_rgba(const Image& rgba, int out_w, int out_h) {
  if (out_w == rgba.width && out_h == rgba.height) return rgba;
  bool opaque = true;
  for (size_t p = 3; p < rgba.pixels.size() && opaque; p += 4) opaque = rgba.pixels[p] == 1.0f;
  if (opaque) {  // nothing to premultiply
    Image out(out_w, out_h, 4);
    cv::Mat src(rgba.height, rgba.width, CV_32FC4, const_cast<float*>(rgba.pixels.data()));
    cv::Mat dst(out_h, out_w, CV_32FC4, out.pixels.data());
    cv::resize(src, dst, dst.size(), 0, 0, cv::INTER_AREA);
    return out;
  }
  Image pre = rgba;
  for (size_t p = 0; p < pre.pixels.size(); p += 4)
    for (int c = 0; c < 3; ++c) pre.pixels[p + c] *= pre.pixels[p + 3];
  cv::Mat src(pre.height, pre.width, CV_32FC4, pre.pixels.data());
  Image out(out_w, out_h, 4);
  cv::Mat dst(out_h, out_w, CV_32FC4, out.pixels.data());
  cv::resize(src, dst, dst.size(), 0, 0, cv::INTER_AREA);
  for (size_t p = 0; p < out.pixels.size(); p += 4) {
    float a = out.pixels[p + 3];
    for (int c = 0; c < 3; ++c) out.pixels[p + c] = a > 0.0f ? out.pixels[p + c] / a : 0.0f;
  }
  return out;
}

}  // namespace lorgnette::dataset::detail
