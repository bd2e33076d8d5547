// Media outputs shared by render, eval and the demo: MP4 videos (OpenCV VideoWriter over FFmpeg),
// contact sheets (a grid of labelled thumbnails), and the evaluation error image
// (prediction | truth | heat map of the absolute error). Inputs are our linear float Images (RGB or
// RGBA; RGBA is composited over a background colour). Every file is written atomically: to a
// temporary name in the same directory, renamed into place only when complete, so an interrupted
// run never leaves a half-written file under the final name.
#pragma once
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "host/util/image_io.h"

namespace lorgnette::dataset {

struct VideoOptions {
  double fps = 30.0;
  std::array<float, 3> background{1.0f, 1.0f, 1.0f};  // linear RGB under RGBA frames (and padding)
};

// Streams frames into an MP4 without keeping them in memory. Codec: H.264 ('avc1', through
// FFmpeg's libx264 on Debian 12) with MPEG-4 part 2 ('mp4v') as fallback; the constructor throws
// when neither works (install ffmpeg/libavcodec with libx264). H.264 needs even dimensions: odd
// widths/heights are padded by one pixel of background on the right/bottom.
class Mp4Writer {
 public:
  Mp4Writer(const std::string& path, int width, int height, const VideoOptions& options = {});
  ~Mp4Writer();  // without finish(): the temporary file is removed, nothing appears at `path`
  Mp4Writer(const Mp4Writer&) = delete;
  Mp4Writer& operator=(const Mp4Writer&) = delete;

  void add(const Image& frame);  // must be width x height, 3 or 4 channels
  void finish();                 // closes and renames into place; throws when no frame was added
  const std::string& codec() const { return codec_; }
  int frames() const { return frames_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string path_, temp_, codec_;
  int width_, height_, frames_ = 0;
  VideoOptions options_;
};

// All frames at once; they must share one size. Returns the codec used ("avc1" or "mp4v").
std::string write_mp4(const std::string& path, const std::vector<Image>& frames,
                      const VideoOptions& options = {});

struct ContactSheetOptions {
  int columns = 0;        // 0: ceil(sqrt(n))
  int cell_width = 256;   // thumbnail cell width; the cell height follows the first image's aspect
  int padding = 8;        // background pixels around and between cells
  int label_height = 20;  // strip below each thumbnail for its label (0 or no labels: none)
  std::array<float, 3> background{1.0f, 1.0f, 1.0f};
  std::array<float, 3> text_colour{0.0f, 0.0f, 0.0f};
};

// Layout: cell i is at column i % columns, row i / columns; its thumbnail (scaled with area
// averaging to fit cell_width x cell_height, centred) has its top-left corner at
// x = padding + col * (cell_width + padding) + centring offset,
// y = padding + row * (cell_height + label_height + padding). labels: empty or one per image.
// Returns 3-channel linear RGB.
Image make_contact_sheet(const std::vector<Image>& images, const std::vector<std::string>& labels,
                         const ContactSheetOptions& options = {});
void write_contact_sheet(const std::string& path, const std::vector<Image>& images,
                         const std::vector<std::string>& labels, const ContactSheetOptions& options = {});

struct ErrorImageOptions {
  // Absolute error (sRGB-encoded, mean over RGB) shown at the top of the colour map; larger errors
  // saturate. 0.25 makes typical NeRF errors (a few percent) visible.
  float max_error = 0.25f;
  std::array<float, 3> background{1.0f, 1.0f, 1.0f};  // under RGBA inputs
};

// Side by side, 3 * width x height, linear RGB: prediction | truth | error heat map (OpenCV's
// INFERNO colour map: black = no error, yellow = max_error or more).
Image make_error_image(const Image& prediction, const Image& truth, const ErrorImageOptions& options = {});

}  // namespace lorgnette::dataset
