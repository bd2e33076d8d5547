// Shared parts of the COLMAP model IO: camera model table, quaternion conversions, and choosing the
// binary or text layout of a model folder.
#include "capture/colmap_model.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "capture/colmap_model_io.h"
#include "host/util/file_kind.h"

namespace lorgnette::capture {
namespace {

struct ModelInfo {
  int id;
  const char* name;
  size_t params;
};
// COLMAP 3.x src/base/camera_models.h, in id order.
constexpr ModelInfo kModels[] = {{0, "SIMPLE_PINHOLE", 3},
                                 {1, "PINHOLE", 4},
                                 {2, "SIMPLE_RADIAL", 4},
                                 {3, "RADIAL", 5},
                                 {4, "OPENCV", 8},
                                 {5, "OPENCV_FISHEYE", 8},
                                 {6, "FULL_OPENCV", 12},
                                 {7, "FOV", 5},
                                 {8, "SIMPLE_RADIAL_FISHEYE", 4},
                                 {9, "RADIAL_FISHEYE", 5},
                                 {10, "THIN_PRISM_FISHEYE", 12}};

const ModelInfo& find_model(const std::string& name) {
  for (const auto& m : kModels)
    if (name == m.name) return m;
  throw std::runtime_error(fmt::format("unknown COLMAP camera model '{}'", name));
}

}  // namespace

int colmap_camera_model_id(const std::string& name) { return find_model(name).id; }

std::string colmap_camera_model_name(int id) {
  for (const auto& m : kModels)
    if (m.id == id) return m.name;
  throw std::runtime_error(fmt::format("unknown COLMAP camera model id {}", id));
}

size_t colmap_camera_param_count(const std::string& name) { return find_model(name).params; }

Eigen::Matrix3d colmap_qvec_to_rotation(const Eigen::Vector4d& q) {
  Eigen::Quaterniond quat(q[0], q[1], q[2], q[3]);
  if (quat.norm() < 1e-12) throw std::runtime_error("COLMAP image has a zero quaternion");
  return quat.normalized().toRotationMatrix();
}

Eigen::Vector4d colmap_rotation_to_qvec(const Eigen::Matrix3d& r) {
  Eigen::Quaterniond q(r);
  q.normalize();
  Eigen::Vector4d v(q.w(), q.x(), q.y(), q.z());
  return v[0] < 0 ? Eigen::Vector4d(-v) : v;
}

namespace {
bool has_all(const std::filesystem::path& dir, const char* ext) {
  for (const char* stem : {"cameras", "images", "points3D"})
    if (!std::filesystem::is_regular_file(dir / (std::string(stem) + ext))) return false;
  return true;
}
}  // namespace

bool is_colmap_model_dir(const std::filesystem::path& dir) {
  return has_all(dir, ".bin") || has_all(dir, ".txt");
}

ColmapModel read_colmap_model(const std::filesystem::path& dir) {
  ColmapModel model;
  if (has_all(dir, ".bin")) {
    model.cameras = read_cameras_binary(dir / "cameras.bin");
    model.images = read_images_binary(dir / "images.bin");
    model.points = read_points3d_binary(dir / "points3D.bin");
  } else if (has_all(dir, ".txt")) {
    model.cameras = read_cameras_text(dir / "cameras.txt");
    model.images = read_images_text(dir / "images.txt");
    model.points = read_points3d_text(dir / "points3D.txt");
  } else {
    throw std::runtime_error(fmt::format(
        "'{}' is not a COLMAP model folder: expected cameras, images and points3D as .bin or .txt",
        dir.string()));
  }
  for (const auto& [id, image] : model.images)
    if (!model.cameras.count(image.camera_id))
      throw std::runtime_error(fmt::format("COLMAP model '{}': image '{}' refers to missing camera {}",
                                           dir.string(), image.name, image.camera_id));
  return model;
}

void write_colmap_model(const ColmapModel& model, const std::filesystem::path& dir, bool binary) {
  std::filesystem::create_directories(dir);
  if (binary) {
    write_cameras_binary(model.cameras, dir / "cameras.bin");
    write_images_binary(model.images, dir / "images.bin");
    write_points3d_binary(model.points, dir / "points3D.bin");
  } else {
    write_cameras_text(model.cameras, dir / "cameras.txt");
    write_images_text(model.images, dir / "images.txt");
    write_points3d_text(model.points, dir / "points3D.txt");
  }
}

std::string read_colmap_file(const std::filesystem::path& path) {
  return read_regular_file(path.string(), "COLMAP file");
}

}  // namespace lorgnette::capture
