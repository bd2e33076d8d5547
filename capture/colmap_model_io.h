// Per-file readers and writers of COLMAP's binary (.bin, little-endian) and text (.txt) model
// layouts; colmap_model.h combines them into whole-folder IO. Internal to capture/.
#pragma once
#include <filesystem>
#include <map>
#include <string>

#include "capture/colmap_model.h"

namespace lorgnette::capture {

using CameraMap = std::map<uint32_t, ColmapCamera>;
using ImageMap = std::map<uint32_t, ColmapImage>;
using PointMap = std::map<uint64_t, ColmapPoint3D>;

// The whole file, which the readers below parse; a file that cannot be opened is an error naming it.
std::string read_colmap_file(const std::filesystem::path& path);

CameraMap read_cameras_binary(const std::filesystem::path& path);
ImageMap read_images_binary(const std::filesystem::path& path);
PointMap read_points3d_binary(const std::filesystem::path& path);
void write_cameras_binary(const CameraMap& cameras, const std::filesystem::path& path);
void write_images_binary(const ImageMap& images, const std::filesystem::path& path);
void write_points3d_binary(const PointMap& points, const std::filesystem::path& path);

CameraMap read_cameras_text(const std::filesystem::path& path);
ImageMap read_images_text(const std::filesystem::path& path);
PointMap read_points3d_text(const std::filesystem::path& path);

// The readers on a file's bytes (what the read_* functions do after reading the file); `name`
// stands for the file in error messages.
CameraMap parse_cameras_binary(std::string bytes, const std::string& name);
ImageMap parse_images_binary(std::string bytes, const std::string& name);
PointMap parse_points3d_binary(std::string bytes, const std::string& name);
CameraMap parse_cameras_text(const std::string& text, const std::string& name);
ImageMap parse_images_text(const std::string& text, const std::string& name);
PointMap parse_points3d_text(const std::string& text, const std::string& name);
void write_cameras_text(const CameraMap& cameras, const std::filesystem::path& path);
void write_images_text(const ImageMap& images, const std::filesystem::path& path);
void write_points3d_text(const PointMap& points, const std::filesystem::path& path);

}  // namespace lorgnette::capture
