// write_transforms_json: the writer side of the dataset format, used by `synth` and `capture`.
// Intrinsics are written at the top level when every camera shares them (the common case), per
// frame otherwise; floats are written as the exact double value of the float so a load gives back
// bitwise the same Camera.
#include <fmt/format.h>

#include <filesystem>
#include <stdexcept>

#include "host/dataset/dataset.h"

namespace lorgnette::dataset {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json intrinsics_json(const Camera& c) {
  return json{{"camera_model", "OPENCV"},
              {"fl_x", static_cast<double>(c.fx)},
              {"fl_y", static_cast<double>(c.fy)},
              {"cx", static_cast<double>(c.cx)},
              {"cy", static_cast<double>(c.cy)},
              {"w", c.width},
              {"h", c.height},
              {"k1", static_cast<double>(c.k1)},
              {"k2", static_cast<double>(c.k2)},
              {"p1", static_cast<double>(c.p1)},
              {"p2", static_cast<double>(c.p2)}};
}

json pose_json(const Camera& c) {
  json m = json::array();
  for (int r = 0; r < 3; ++r) {
    json row = json::array();
    for (int k = 0; k < 4; ++k) row.push_back(static_cast<double>(c.c2w[r * 4 + k]));
    m.push_back(row);
  }
  m.push_back(json::array({0.0, 0.0, 0.0, 1.0}));
  return m;
}

}  // namespace

void write_transforms_json(const std::string& dir, const std::vector<Camera>& cameras,
                           const std::vector<std::string>& image_files, const json& extra) {
  if (cameras.empty()) throw std::runtime_error("write_transforms_json: no cameras to write");
  if (cameras.size() != image_files.size())
    throw std::runtime_error(fmt::format("write_transforms_json: {} cameras but {} image file names",
                                         cameras.size(), image_files.size()));
  if (!extra.is_object()) throw std::runtime_error("write_transforms_json: 'extra' must be a JSON object");
  json shared = intrinsics_json(cameras[0]);
  bool all_same = true;
  for (const Camera& c : cameras) all_same = all_same && intrinsics_json(c) == shared;

  json doc = all_same ? shared : json{{"camera_model", "OPENCV"}};
  json frames = json::array();
  for (size_t i = 0; i < cameras.size(); ++i) {
    json f = all_same ? json::object() : intrinsics_json(cameras[i]);
    f.erase("camera_model");
    f["file_path"] = image_files[i];
    f["transform_matrix"] = pose_json(cameras[i]);
    frames.push_back(std::move(f));
  }
  doc["frames"] = std::move(frames);
  for (auto it = extra.begin(); it != extra.end(); ++it) doc[it.key()] = it.value();

  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec)
    throw std::runtime_error(fmt::format("cannot create dataset directory '{}': {}", dir, ec.message()));
  write_text_file_atomic((fs::path(dir) / "transforms.json").string(), doc.dump(2));
}

}  // namespace lorgnette::dataset
