// Mp4Writer and write_mp4: OpenCV's FFmpeg VideoWriter into a temporary file renamed into place on
// finish(). See media.h for the codec choice and padding rule.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/videoio.hpp>
#include <stdexcept>
#include <vector>

#include "host/dataset/media.h"
#include "host/dataset/metrics.h"
#include "host/util/file_write.h"

namespace lorgnette::dataset {
namespace fs = std::filesystem;

namespace {

// Linear -> 8-bit sRGB by binary search over the 255 linear thresholds between codes: the same code
// as round(linear_to_srgb(v) * 255) up to float rounding at the thresholds, without a pow per
// sample (a 1280x720 frame has 2.8 M samples).
uint8_t encode_srgb8(float v) {
  static const std::vector<float> thresholds = [] {
    std::vector<float> t(255);
    for (int k = 0; k < 255; ++k) t[k] = srgb_to_linear((k + 0.5f) / 255.0f);
    return t;
  }();
  return static_cast<uint8_t>(std::upper_bound(thresholds.begin(), thresholds.end(), v) - thresholds.begin());
}

// True when the video at `path` opens and reports at least `frames` frames.
bool holds_frames(const std::string& path, int frames) {
  cv::VideoCapture cap(path, cv::CAP_FFMPEG);
  return cap.isOpened() && cap.get(cv::CAP_PROP_FRAME_COUNT) >= frames;
}

}  // namespace

struct Mp4Writer::Impl {
  cv::VideoWriter writer;
};

Mp4Writer::Mp4Writer(const std::string& path, int width, int height, const VideoOptions& options)
    : impl_(std::make_unique<Impl>()), path_(path), width_(width), height_(height), options_(options) {
  if (width <= 0 || height <= 0 || !(options.fps > 0))
    throw std::runtime_error(
        fmt::format("cannot write video '{}': bad size {}x{} or fps {}", path, width, height, options.fps));
  fs::path p(path);
  fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw std::runtime_error(
        fmt::format("cannot write video '{}': directory '{}' does not exist", path, dir.string()));
  // Keep ".mp4" last so FFmpeg picks the MP4 container for the temporary file.
  temp_ = (dir / fmt::format(".{}.{}.tmp.mp4", p.stem().string(), getpid())).string();
  cv::Size size(width + width % 2, height + height % 2);
  auto level = cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_ERROR);
  for (const char* cc : {"avc1", "mp4v"}) {
    if (impl_->writer.open(temp_, cv::CAP_FFMPEG, cv::VideoWriter::fourcc(cc[0], cc[1], cc[2], cc[3]),
                           options.fps, size) &&
        impl_->writer.isOpened()) {
      codec_ = cc;
      break;
    }
  }
  cv::utils::logging::setLogLevel(level);
  if (codec_.empty()) {
    fs::remove(temp_, ec);
    // A full disk or a read-only folder is the likelier reason: said as such when it is.
    check_writable_folder(dir.string(), fmt::format("the video '{}'", path));
    throw std::runtime_error(fmt::format(
        "cannot write video '{}': OpenCV's FFmpeg backend opened neither H.264 ('avc1') nor MPEG-4 ('mp4v'); "
        "check "
        "that the directory is writable and that libopencv-videoio and ffmpeg (libavcodec with libx264) are "
        "installed",
        path));
  }
}

Mp4Writer::~Mp4Writer() {
  if (impl_ && impl_->writer.isOpened()) impl_->writer.release();
  std::error_code ec;
  if (!temp_.empty()) fs::remove(temp_, ec);
}

void Mp4Writer::add(const Image& frame) {
  if (!impl_->writer.isOpened())
    throw std::runtime_error(fmt::format("video '{}' is already finished", path_));
  if (frame.width != width_ || frame.height != height_)
    throw std::runtime_error(
        fmt::format("video '{}': frame {} is {}x{}, expected {}x{} (all frames must match)", path_, frames_,
                    frame.width, frame.height, width_, height_));
  Image rgb = composite_over(frame, options_.background);
  int w = width_ + width_ % 2, h = height_ + height_ % 2;
  cv::Mat bgr(h, w, CV_8UC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      bool inside = x < width_ && y < height_;
      for (int c = 0; c < 3; ++c) {
        float v = inside ? rgb.at(x, y, c) : options_.background[c];
        bgr.at<cv::Vec3b>(y, x)[2 - c] = encode_srgb8(v);
      }
    }
  impl_->writer.write(bgr);
  ++frames_;
}

void Mp4Writer::finish() {
  if (frames_ == 0) throw std::runtime_error(fmt::format("video '{}': no frames were added", path_));
  impl_->writer.release();
  std::error_code ec;
  // The encoder does not report a full disk: the finished file must open and hold every frame (an
  // MP4 cut short lacks the index written at its end).
  if (!fs::exists(temp_, ec) || fs::file_size(temp_, ec) == 0 || !holds_frames(temp_, frames_))
    throw std::runtime_error(fmt::format(
        "cannot write video '{}': the encoder's file is short or unreadable (is the disk full?)", path_));
  fs::rename(temp_, path_, ec);
  if (ec) throw std::runtime_error(fmt::format("cannot write video '{}': {}", path_, ec.message()));
  temp_.clear();
}

std::string write_mp4(const std::string& path, const std::vector<Image>& frames,
                      const VideoOptions& options) {
  if (frames.empty()) throw std::runtime_error(fmt::format("video '{}': no frames to write", path));
  Mp4Writer writer(path, frames[0].width, frames[0].height, options);
  for (const Image& f : frames) writer.add(f);
  writer.finish();
  return writer.codec();
}

}  // namespace lorgnette::dataset
