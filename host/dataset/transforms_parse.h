// Internal to the dataset loader: parsing of transforms json files into per-frame specifications
// (image file, pose, intrinsics as declared) and their validation. The intrinsics are resolved
// against the real image size later, in dataset.cpp, because NeRF-synthetic files declare only a
// field of view and the image size comes from the image itself.
#pragma once
#include <Eigen/Core>
#include <array>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "host/dataset/dataset.h"

namespace lorgnette::dataset::detail {

// Intrinsics as a json object declares them (top level or per frame); absent values stay empty.
struct DeclaredIntrinsics {
  std::optional<double> fl_x, fl_y, cx, cy, angle_x, angle_y;
  std::optional<int> w, h;
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0;
};

struct FrameSpec {
  std::string where;           // for messages: "frame 3 ('./train/r_3') of transforms_train.json"
  std::string file_path;       // as written in the json
  std::string image_path;      // resolved path ("" when the file is missing)
  std::string mask_file_path;  // nerfstudio "mask_path" as written ("" when the frame has none)
  std::string mask_path;       // resolved path ("" when none is declared or the file is missing)
  Split split = Split::Train;
  Eigen::Matrix4d c2w = Eigen::Matrix4d::Identity();
  DeclaredIntrinsics intrinsics;
};

// Reads and parses one json file; errors name the file and say what to do.
nlohmann::json read_json_file(const std::string& path);

// Top-level intrinsics of a transforms file, after checking the camera model is supported.
DeclaredIntrinsics parse_intrinsics(const nlohmann::json& obj, const DeclaredIntrinsics& base,
                                    const std::string& where);

// All frames of one transforms file (split = `split`), intrinsics merged with the top level.
std::vector<FrameSpec> parse_frames(const nlohmann::json& doc, const std::string& json_path, Split split);

// The 4x4 (or 3x4) matrix under `key`, checked: numbers only, finite, rigid (orthonormal rotation
// with det +1 to 1e-3), bottom row 0 0 0 1.
Eigen::Matrix4d parse_pose(const nlohmann::json& value, const std::string& where);
// "aabb": [[min x, y, z], [max x, y, z]], finite, max > min on every axis; throws naming `where`.
std::array<std::array<float, 3>, 2> parse_aabb(const nlohmann::json& value, const std::string& where);

// nerfstudio's rule: "mask_path" on every frame of `frames` or on none; throws naming the first
// frame without one otherwise.
void check_masks_all_or_none(const std::vector<FrameSpec>& frames, const std::string& json_path);

// Throws when all camera centres coincide (no parallax: nothing can be reconstructed).
void check_not_degenerate(const std::vector<FrameSpec>& frames);

// Resolves a json file_path relative to `dir`, trying common image extensions when it has none.
// Returns "" when no file exists.
std::string resolve_image_path(const std::string& dir, const std::string& file_path);

// Final camera intrinsics for an image of width x height pixels, as the file declares them.
Camera make_camera(const FrameSpec& spec, int width, int height);

}  // namespace lorgnette::dataset::detail
