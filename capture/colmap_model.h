// COLMAP sparse models in memory and on disk: cameras, registered images (world-to-camera
// quaternion + translation, 2D observations) and 3D points with their tracks, read from and written
// to both of COLMAP's layouts (cameras/images/points3D as .bin or .txt, as COLMAP 3.x writes them).
// No Debian library reads these files, so this is a small self-contained reader/writer.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace lorgnette::capture {

struct ColmapCamera {
  uint32_t id = 0;
  std::string model;  // COLMAP model name: PINHOLE, SIMPLE_RADIAL, OPENCV, ...
  uint64_t width = 0, height = 0;
  std::vector<double> params;  // in COLMAP's order for the model
};

struct ColmapImage {
  uint32_t id = 0;
  Eigen::Vector4d qvec{1, 0, 0, 0};                // world-to-camera rotation, (w, x, y, z)
  Eigen::Vector3d tvec = Eigen::Vector3d::Zero();  // world-to-camera translation
  uint32_t camera_id = 0;
  std::string name;  // path relative to the image folder
  std::vector<Eigen::Vector2d> xys;
  std::vector<int64_t> point3d_ids;  // -1 where the observation has no 3D point
};

struct ColmapPoint3D {
  uint64_t id = 0;
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
  uint8_t rgb[3] = {0, 0, 0};
  double error = 0;                                  // mean reprojection error in pixels
  std::vector<std::pair<uint32_t, uint32_t>> track;  // (image id, point2D index)
};

struct ColmapModel {
  std::map<uint32_t, ColmapCamera> cameras;
  std::map<uint32_t, ColmapImage> images;
  std::map<uint64_t, ColmapPoint3D> points;
};

// COLMAP's numeric model id and parameter count for a model name; throw for an unknown name.
int colmap_camera_model_id(const std::string& name);
std::string colmap_camera_model_name(int id);
size_t colmap_camera_param_count(const std::string& name);

// True when `dir` holds cameras+images+points3D in either layout.
bool is_colmap_model_dir(const std::filesystem::path& dir);
// Reads a model folder (binary preferred when both layouts are present). Throws with the file and
// what is wrong (missing file, truncated or malformed record).
ColmapModel read_colmap_model(const std::filesystem::path& dir);
// Writes cameras/images/points3D (.bin when `binary`, else .txt with round-trip precision).
void write_colmap_model(const ColmapModel& model, const std::filesystem::path& dir, bool binary);

// World-to-camera rotation of a COLMAP (w, x, y, z) quaternion, and back (w >= 0).
Eigen::Matrix3d colmap_qvec_to_rotation(const Eigen::Vector4d& q);
Eigen::Vector4d colmap_rotation_to_qvec(const Eigen::Matrix3d& r);

}  // namespace lorgnette::capture
