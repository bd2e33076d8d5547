// Frame sources for `lorgnette capture`: input classification, video sampling, image folders.
#include "capture/frame_source.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <stdexcept>

#include "capture/colmap_model.h"
#include "host/util/interrupt.h"
#include "host/util/progress.h"

namespace fs = std::filesystem;

namespace lorgnette::capture {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

bool is_image_file(const fs::path& p) {
  static const char* exts[] = {".jpg", ".jpeg", ".png", ".bmp", ".tif", ".tiff"};
  std::string e = lower(p.extension().string());
  return std::any_of(std::begin(exts), std::end(exts), [&](const char* x) { return e == x; });
}

cv::Mat fit_size(const cv::Mat& img, int max_side) {
  int side = std::max(img.cols, img.rows);
  if (max_side <= 0 || side <= max_side) return img;
  double s = static_cast<double>(max_side) / side;
  cv::Mat out;
  cv::resize(
      img, out,
      cv::Size(static_cast<int>(std::lround(img.cols * s)), static_cast<int>(std::lround(img.rows * s))), 0,
      0, cv::INTER_AREA);
  return out;
}

}  // namespace

std::vector<size_t> even_subsample(size_t total, size_t count) {
  std::vector<size_t> idx;
  if (count == 0 || count >= total) {
    for (size_t i = 0; i < total; ++i) idx.push_back(i);
    return idx;
  }
  for (size_t k = 0; k < count; ++k) idx.push_back(k * total / count);
  return idx;
}

std::vector<fs::path> list_images(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && is_image_file(e.path())) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

CaptureInput classify_input(const fs::path& path) {
  CaptureInput in;
  in.path = path;
  if (!fs::exists(path))
    throw std::runtime_error(
        fmt::format("input '{}' does not exist: give a video file, a folder of "
                    "images, or a folder holding a COLMAP model",
                    path.string()));
  if (fs::is_regular_file(path)) {
    in.kind = InputKind::Video;
    return in;
  }
  for (const fs::path& m : {path / "sparse" / "0", path / "sparse", path}) {
    if (fs::is_directory(m) && is_colmap_model_dir(m)) {
      in.kind = InputKind::ColmapModel;
      in.model_dir = m;
      in.image_dir = path / "images";
      return in;
    }
  }
  in.kind = InputKind::ImageFolder;
  in.image_dir = path;
  if (list_images(path).empty()) {
    bool nested = fs::is_directory(path / "images") && !list_images(path / "images").empty();
    throw std::runtime_error(fmt::format(
        "no images (.jpg, .jpeg, .png, .bmp, .tif) in '{}'{}", path.string(),
        nested ? fmt::format(": did you mean '{}'?", (path / "images").string())
               : ": give a folder of photos, a video file, or a folder with a COLMAP model (sparse/0)"));
  }
  return in;
}

FrameSet read_image_folder(const fs::path& dir, const FrameOptions& opt) {
  auto files = list_images(dir);
  if (files.empty()) throw std::runtime_error(fmt::format("no images in '{}'", dir.string()));
  FrameSet set;
  set.source_frames = files.size();
  auto pick = even_subsample(files.size(), opt.max_frames > 0 ? opt.max_frames : 0);
  Progress progress("frames", static_cast<double>(pick.size()), "img");
  for (size_t k = 0; k < pick.size() && !interrupted(); ++k) {
    const fs::path& f = files[pick[k]];
    cv::Mat img = cv::imread(f.string(), cv::IMREAD_COLOR);
    if (img.empty())
      throw std::runtime_error(
          fmt::format("cannot read image '{}': not an image OpenCV can decode "
                      "(remove it or convert it to JPEG/PNG)",
                      f.string()));
    set.images.push_back(fit_size(img, opt.max_side));
    // Resized frames are re-encoded as JPEG, so the name says so.
    set.names.push_back(f.stem().string() + ".jpg");
    progress.update(k + 1.0, f.filename().string());
  }
  progress.finish();
  return set;
}

FrameSet read_video_frames(const fs::path& video, const FrameOptions& opt) {
  cv::VideoCapture cap(video.string(), cv::CAP_FFMPEG);  // not GStreamer: it prints noise on failure
  if (!cap.isOpened())
    throw std::runtime_error(
        fmt::format("cannot open video '{}': not a video OpenCV/FFmpeg can "
                    "decode (give an .mp4/.mov, or a folder of photos)",
                    video.string()));
  FrameSet set;
  set.source_fps = cap.get(cv::CAP_PROP_FPS);
  double count = cap.get(cv::CAP_PROP_FRAME_COUNT);
  if (!(set.source_fps > 0)) set.source_fps = 30;  // unknown rate: assume a phone's 30 fps
  double step = opt.fps > 0 ? std::max(1.0, set.source_fps / opt.fps) : 1.0;
  Progress progress("frames", count > 0 ? count : 1.0, "frame");
  cv::Mat frame;
  double next = 0;
  size_t index = 0;
  std::vector<cv::Mat> sampled;
  while (!interrupted() && cap.read(frame)) {
    if (static_cast<double>(index) + 1e-9 >= next) {
      sampled.push_back(fit_size(frame, opt.max_side).clone());
      next += step;
    }
    ++index;
    if (index % 10 == 0) progress.update(static_cast<double>(index));
  }
  progress.finish(fmt::format("{} of {} frames sampled", sampled.size(), index));
  set.source_frames = index;
  if (sampled.empty())
    throw std::runtime_error(fmt::format("video '{}' has no decodable frames", video.string()));
  auto pick = even_subsample(sampled.size(), opt.max_frames > 0 ? opt.max_frames : 0);
  for (size_t k = 0; k < pick.size(); ++k) {
    set.images.push_back(sampled[pick[k]]);
    set.names.push_back(fmt::format("frame_{:05d}.jpg", k + 1));
  }
  return set;
}

}  // namespace lorgnette::capture
