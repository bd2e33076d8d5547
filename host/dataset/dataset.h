// Dataset loading for training and evaluation: instant-ngp / nerfstudio `transforms.json` and the
// NeRF-synthetic `transforms_{train,val,test}.json` triple, into Cameras (kernels/common/camera_types.h)
// and linear float RGBA images. Poses are kept in the file's convention (camera-to-world, OpenGL style:
// the camera looks down -z, +y up), which is exactly our Camera's, so nothing is flipped.
//
// Conventions decided here (documented once, relied on by train/eval):
// - Splits: NeRF-synthetic train/val/test are taken as given. A single transforms.json has no splits:
//   frames are sorted by file path (as nerfstudio does, so the order does not depend on how the file
//   was written) and every 8th one (sorted index % 8 == 0) is the "holdout" split, never trained on;
//   the rest is "train".
// - `applied_transform` (nerfstudio): the 3x4 transform nerfstudio's data processing ALREADY applied
//   to the poses (e.g. a COLMAP world -> nerfstudio world axis swap). The poses in the file are in the
//   transformed frame, which is our scene frame; we do not apply it again. It is kept (as a 4x4) so any
//   output can be mapped back to the original capture frame: p_original = applied_transform^-1 * p_scene.
// - `aabb_scale`, `scale`, `offset` (instant-ngp) are recorded as hints only; poses are not rescaled.
// - Images are always returned with 4 channels, linear RGB + alpha (alpha = 1 where the file has none).
//   RGBA images keep their alpha: the trainer composites onto a random background colour.
// - Mattes: a frame's nerfstudio "mask_path" (on every frame or none; any image whose first channel
//   is coverage, 0 = background, 8-bit v / 255, 0/1 masks as binary) multiplies its alpha, so the
//   subject is separated by the mattes as with RGBA images (has_alpha is set; train then needs no
//   room model). A missing mask or one of another size than its image is an error.
// - Ignore regions (ignore_regions.json beside the json, ignore_regions.h): each listed frame's
//   polygons, scaled to its loaded size, in Frame::ignore. A name that matches no frame of the json
//   (all splits) is an error: the file belongs to another dataset.
// - Downscaling resizes images with area averaging and scales intrinsics by the exact per-axis size
//   ratio (new_w / w, new_h / h), which keeps the pixel-centre convention of camera_types.h.
#pragma once
#include <Eigen/Core>
#include <array>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/camera_types.h"
#include "host/dataset/ignore_regions.h"
#include "host/util/image_io.h"

namespace lorgnette::dataset {

enum class Split { Train, Val, Test, Holdout };

// "train", "val", "test", "holdout"; split_from_string throws on anything else (listing the names).
const char* to_string(Split split);
Split split_from_string(const std::string& name);

// Frames that must remain after those with missing images are skipped (capture's own minimum).
constexpr size_t kMinFramesLeft = 3;

struct LoadOptions {
  int downscale = 1;   // integer factor >= 1 applied to every image (and its intrinsics)
  int max_side = 0;    // > 0: further shrink so that max(width, height) <= max_side
  int max_frames = 0;  // > 0: keep at most this many frames PER SPLIT, evenly spaced
  // > 0: when the images, as loaded (linear float RGBA, 16 bytes a pixel, after downscale and
  // max_side), would hold more than this many bytes, shrink them all by one factor (as a smaller
  // max_side would) until they fit, and log it. A phone capture of 300 1080p frames holds 10 GB;
  // training uploads them to the device in one buffer.
  uint64_t max_image_bytes = 0;
  bool load_images = true;  // false: cameras only (image headers are still read to check sizes)
  // Splits to load (empty = all). NeRF-synthetic: only the needed json files are read. For a plain
  // transforms.json the train/holdout assignment is always made on the full list first.
  std::vector<Split> splits;
  // Frames whose image file is missing are skipped with a warning that counts and names them, as
  // `capture` drops them (the instant-ngp fox sample lists 67 frames for 50 photos). Too few left is an
  // error that says what to do: fewer than kMinFramesLeft, or fewer than half of the frames wanted (a
  // wrong or half-copied image folder rather than a few lost photos). true: skip however many are
  // missing (users of the cameras alone, e.g. the renderer's capture arc).
  bool any_missing_images_ok = false;
};

struct Frame {
  std::string name;        // file stem, e.g. "r_0" or "frame_00065"
  std::string image_path;  // resolved absolute path of the image file
  Split split = Split::Train;
  Camera camera{};  // intrinsics already scaled to the loaded image size
  Image image;      // width x height x 4, linear RGBA; empty when !LoadOptions::load_images
  // Regions of this frame training leaves out (ignore_regions.h), in the loaded image's pixels;
  // empty for most frames.
  std::vector<IgnorePolygon> ignore;
};

struct Dataset {
  std::string root;           // directory holding the json file(s)
  std::string format;         // "nerf-synthetic" or "transforms"
  std::vector<Frame> frames;  // all loaded frames, split by Frame::split
  bool has_alpha = false;     // any loaded image file had an alpha channel

  // Transform already applied to the poses by nerfstudio (identity when absent); see the top of file.
  Eigen::Matrix4d applied_transform = Eigen::Matrix4d::Identity();
  bool has_applied_transform = false;
  float aabb_scale = 1.0f;                     // instant-ngp hint (1 when absent)
  std::optional<float> scale;                  // instant-ngp "scale" if present (not applied)
  std::optional<std::array<float, 3>> offset;  // instant-ngp "offset" if present (not applied)
  std::optional<double> mm_per_unit;           // from ground_truth.json beside the json, if any
  // "aabb": [[min x, y, z], [max x, y, z]] in scene units, the subject's box (written by `capture`);
  // training uses it instead of the automatic box so the room behind a head is ignored.
  std::optional<std::array<std::array<float, 3>, 2>> aabb;
  nlohmann::json ground_truth;  // its full content (null when absent)

  // Frames of a split, in dataset order; an empty list when the split has none.
  std::vector<const Frame*> split(Split s) const;
  bool has_split(Split s) const;
  // The evaluation split to use when the user did not name one: test (NeRF-synthetic) or holdout.
  Split default_eval_split() const;
  // Like split(), but throws a clear error naming the available splits when `s` is empty.
  std::vector<const Frame*> require_split(Split s) const;
  // Axis-aligned box of the camera centres (min, max), over all frames.
  std::pair<Eigen::Vector3f, Eigen::Vector3f> camera_bounds() const;
};

// path: a directory holding transforms.json or transforms_{train,val,test}.json, or one .json file
// (a file named transforms_<split>.json selects the NeRF-synthetic triple of its directory).
// Throws std::runtime_error with what is wrong, which frame/file, and what to do.
Dataset load_dataset(const std::string& path, const LoadOptions& options = {});

// Camera <-> the 4x4 transform_matrix of transforms.json (same OpenGL convention; no conversion).
Eigen::Matrix4d camera_to_matrix(const Camera& cam);
void set_camera_pose(Camera& cam, const Eigen::Matrix4d& c2w);

// Writes `dir`/transforms.json (instant-ngp / nerfstudio style, read back by load_dataset): shared
// intrinsics at the top level when all cameras agree, per-frame otherwise; camera_model "OPENCV";
// frames[i] = {file_path: image_files[i] (relative to dir), transform_matrix}. `extra` keys are merged
// into the top level (e.g. aabb_scale, applied_transform, or anything the writer wants to record).
// Written atomically. Throws when sizes disagree or dir is not writable.
void write_transforms_json(const std::string& dir, const std::vector<Camera>& cameras,
                           const std::vector<std::string>& image_files,
                           const nlohmann::json& extra = nlohmann::json::object());

}  // namespace lorgnette::dataset
