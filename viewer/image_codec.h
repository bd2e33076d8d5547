// Frame encoding for the viewer: the marcher's linear RGBA (background already composited) to 8-bit
// sRGB RGB through a lookup table, JPEG through libjpeg-turbo (tjCompress2, one compressor per
// encoder: not thread-safe, one per render thread) and PNG (OpenCV) for full-quality snapshots.
#pragma once
#include <cstdint>
#include <vector>

#include "host/util/image_io.h"

namespace lorgnette::viewer {

struct Rgb8 {
  int width = 0, height = 0;
  std::vector<uint8_t> pixels;  // width * height * 3, sRGB, top row first
};

// Linear RGB(A) -> sRGB 8-bit RGB (alpha ignored: the colour is already over the background).
Rgb8 to_srgb8(const Image& linear);
// Copies `band` into rows [y0, y0 + band.height) of `dst` (same width).
void paste_rows(Rgb8& dst, const Rgb8& band, int y0);

class JpegEncoder {
 public:
  JpegEncoder();
  ~JpegEncoder();
  JpegEncoder(const JpegEncoder&) = delete;
  JpegEncoder& operator=(const JpegEncoder&) = delete;
  // quality 1..100; 4:2:0 subsampling. Throws std::runtime_error with libjpeg-turbo's message.
  std::vector<uint8_t> encode(const Rgb8& image, int quality);

 private:
  void* handle_ = nullptr;  // tjhandle
};

std::vector<uint8_t> encode_png(const Rgb8& image);

}  // namespace lorgnette::viewer
