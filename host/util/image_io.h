// Image files in and out through OpenImageIO. Inside Lorgnette images are linear float RGB(A),
// interleaved, row-major, top row first; 8/16-bit files are sRGB-encoded and converted on the way
// in and out, float files (EXR) stay linear. Writes are atomic and checked (host/util/file_write.h):
// a full disk or an interrupted run never leaves an empty or half-written image under the final name.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace lorgnette {

struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<float> pixels;  // width * height * channels, linear

  Image() = default;
  Image(int w, int h, int c, float value = 0.0f)
      : width(w), height(h), channels(c), pixels(static_cast<size_t>(w) * h * c, value) {}
  float& at(int x, int y, int c) { return pixels[(static_cast<size_t>(y) * width + x) * channels + c]; }
  float at(int x, int y, int c) const { return pixels[(static_cast<size_t>(y) * width + x) * channels + c]; }
  bool empty() const { return pixels.empty(); }
  // True for a 4-channel image with any pixel's alpha below 0.99: an alpha mask, not just an alpha
  // channel that is opaque everywhere.
  bool has_transparency() const {
    if (channels != 4) return false;
    for (size_t i = 3; i < pixels.size(); i += 4)
      if (pixels[i] < 0.99f) return true;
    return false;
  }
};

float srgb_to_linear(float c);
float linear_to_srgb(float c);

// Throws std::runtime_error naming the file and what is wrong (missing, unreadable, corrupt or
// truncated: a decode that reports an error counts as failed even when it returned pixels).
Image read_image(const std::string& path);

// An OpenImageIO error text (often several lines) as one line for a message; a placeholder when empty.
std::string decode_error_text(std::string text);
// Format from the extension: .png/.jpg (sRGB, 8-bit; alpha kept for PNG), .exr/.hdr (linear float).
void write_image(const std::string& path, const Image& image);

// Writes 8-bit pixels that are already sRGB-encoded (interleaved, top row first) as they are, with
// write_image's checks (PNG/JPEG by the extension).
void write_srgb8_image(const std::string& path, int width, int height, int channels, const uint8_t* pixels);

// Writes `text` to `path` through a temporary file and rename (for JSON/CSV outputs); every write
// is checked (host/util/file_write.h).
void write_text_file_atomic(const std::string& path, const std::string& text);

}  // namespace lorgnette
