// Where a capture's frames come from: a video file (frames sampled with OpenCV at a chosen rate), a
// folder of images (sorted by name), or a folder that already holds a COLMAP model (sparse/0 or
// sparse/ or the folder itself, with its images in images/). Frames are resized so their longer
// side is at most `max_side` and evenly subsampled down to `max_frames`.
#pragma once
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace lorgnette::capture {

enum class InputKind { Video, ImageFolder, ColmapModel };

struct CaptureInput {
  InputKind kind = InputKind::ImageFolder;
  std::filesystem::path path;       // what the user gave
  std::filesystem::path model_dir;  // ColmapModel: the folder with cameras/images/points3D
  std::filesystem::path image_dir;  // ImageFolder: path; ColmapModel: its images folder
};

// Throws with what is wrong and what to give instead (missing path, empty folder, ...).
CaptureInput classify_input(const std::filesystem::path& path);

// Image files (jpg/jpeg/png/bmp/tif/tiff, any case) directly inside `dir`, sorted by name.
std::vector<std::filesystem::path> list_images(const std::filesystem::path& dir);

struct FrameSet {
  std::vector<std::string> names;  // output file names (original names for folders)
  std::vector<cv::Mat> images;     // 8-bit BGR
  size_t source_frames = 0;        // frames in the video / images in the folder
  double source_fps = 0;           // video only
};

struct FrameOptions {
  double fps = 2.0;      // video sampling rate (frames per second of video)
  int max_frames = 150;  // <= 0: no limit
  int max_side = 768;    // <= 0: keep the size
};

// Throws when the video cannot be opened/decoded or a folder image cannot be read.
FrameSet read_video_frames(const std::filesystem::path& video, const FrameOptions& options);
FrameSet read_image_folder(const std::filesystem::path& dir, const FrameOptions& options);

// Indices of `count` items evenly spread over [0, total) (all of them when count >= total).
std::vector<size_t> even_subsample(size_t total, size_t count);

}  // namespace lorgnette::capture
