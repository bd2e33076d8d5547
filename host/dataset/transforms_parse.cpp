// Parsing and validation of transforms json files (instant-ngp, nerfstudio, NeRF-synthetic): camera
// model, intrinsics (shared or per frame, focal length or field of view), poses, image paths.
#include "host/dataset/transforms_parse.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "host/util/file_kind.h"

namespace lorgnette::dataset::detail {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::optional<double> number(const json& obj, const char* key, const std::string& where) {
  auto it = obj.find(key);
  if (it == obj.end() || it->is_null()) return std::nullopt;
  if (!it->is_number())
    throw std::runtime_error(fmt::format("{}: '{}' must be a number, found {}", where, key, it->dump()));
  double v = it->get<double>();
  if (!std::isfinite(v)) throw std::runtime_error(fmt::format("{}: '{}' is not finite", where, key));
  return v;
}

std::optional<int> positive_int(const json& obj, const char* key, const std::string& where) {
  auto v = number(obj, key, where);
  if (!v) return std::nullopt;
  if (*v < 1 || *v > std::numeric_limits<int>::max() || *v != std::floor(*v))
    throw std::runtime_error(
        fmt::format("{}: '{}' must be a positive whole number of pixels, found {}", where, key, *v));
  return static_cast<int>(*v);
}

void check_camera_model(const json& obj, const std::string& where) {
  if (auto it = obj.find("camera_model"); it != obj.end()) {
    std::string model = it->is_string() ? it->get<std::string>() : it->dump();
    if (model != "OPENCV" && model != "PINHOLE" && model != "SIMPLE_PINHOLE")
      throw std::runtime_error(
          fmt::format("{}: camera_model '{}' is not supported (supported: OPENCV, PINHOLE, SIMPLE_PINHOLE); "
                      "undistort the "
                      "images first (e.g. COLMAP image_undistorter) or re-run ns-process-data with "
                      "--camera-type perspective",
                      where, model));
  }
  if (auto it = obj.find("is_fisheye"); it != obj.end() && it->is_boolean() && it->get<bool>())
    throw std::runtime_error(
        fmt::format("{}: fisheye cameras (is_fisheye) are not supported; undistort the images "
                    "to a pinhole model first",
                    where));
  for (const char* key : {"k3", "k4"}) {
    auto v = number(obj, key, where);
    if (v && *v != 0.0)
      throw std::runtime_error(
          fmt::format("{}: distortion coefficient '{}' = {} is not supported (only OPENCV k1 k2 "
                      "p1 p2); undistort the images first",
                      where, key, *v));
  }
}

}  // namespace

json read_json_file(const std::string& path) {
  const std::string text = read_regular_file(path, "dataset file");
  try {
    return json::parse(text);
  } catch (const json::out_of_range& e) {
    throw std::runtime_error(
        fmt::format("'{}' holds a number out of range ({}): a pose or value is infinite; fix "
                    "the file or regenerate it",
                    path, e.what()));
  } catch (const json::exception& e) {
    // Python's json module writes NaN/Infinity literals, which JSON does not allow: say so plainly.
    bool non_finite = text.find("NaN") != std::string::npos || text.find("Infinity") != std::string::npos;
    throw std::runtime_error(fmt::format(
        "'{}' is not valid JSON ({}){}; fix the file or regenerate it", path, e.what(),
        non_finite ? ". It contains NaN or Infinity: a pose or value is not finite (a failed registration?)"
                   : ""));
  }
}

DeclaredIntrinsics parse_intrinsics(const json& obj, const DeclaredIntrinsics& base,
                                    const std::string& where) {
  check_camera_model(obj, where);
  DeclaredIntrinsics d = base;
  if (auto v = number(obj, "fl_x", where)) d.fl_x = v;
  if (auto v = number(obj, "fl_y", where)) d.fl_y = v;
  if (auto v = number(obj, "cx", where)) d.cx = v;
  if (auto v = number(obj, "cy", where)) d.cy = v;
  if (auto v = number(obj, "camera_angle_x", where)) d.angle_x = v;
  if (auto v = number(obj, "camera_angle_y", where)) d.angle_y = v;
  if (auto v = positive_int(obj, "w", where)) d.w = v;
  if (auto v = positive_int(obj, "h", where)) d.h = v;
  if (auto v = number(obj, "k1", where)) d.k1 = *v;
  if (auto v = number(obj, "k2", where)) d.k2 = *v;
  if (auto v = number(obj, "p1", where)) d.p1 = *v;
  if (auto v = number(obj, "p2", where)) d.p2 = *v;
  for (auto* f : {&d.fl_x, &d.fl_y})
    if (*f && **f <= 0) throw std::runtime_error(fmt::format("{}: focal length must be positive", where));
  for (auto* a : {&d.angle_x, &d.angle_y})
    if (*a && (**a <= 0 || **a >= M_PI))
      throw std::runtime_error(
          fmt::format("{}: camera_angle must be in (0, pi) radians, found {}", where, **a));
  return d;
}

std::array<std::array<float, 3>, 2> parse_aabb(const json& value, const std::string& where) {
  auto bad = [&] {
    return std::runtime_error(
        fmt::format("{}: 'aabb' must be [[min x, y, z], [max x, y, z]] with finite numbers and "
                    "max > min on every axis; fix or remove it",
                    where));
  };
  if (!value.is_array() || value.size() != 2) throw bad();
  std::array<std::array<float, 3>, 2> box{};
  for (int c = 0; c < 2; ++c) {
    if (!value[c].is_array() || value[c].size() != 3) throw bad();
    for (int i = 0; i < 3; ++i) {
      double v = value[c][i].is_number() ? value[c][i].get<double>() : NAN;
      if (!(std::abs(v) <= std::numeric_limits<float>::max())) throw bad();  // finite as a float too
      box[c][i] = static_cast<float>(v);
    }
  }
  for (int i = 0; i < 3; ++i)
    if (!(box[1][i] > box[0][i])) throw bad();
  return box;
}

Eigen::Matrix4d parse_pose(const json& value, const std::string& where) {
  const char* fix = "; each frame needs a 4x4 camera-to-world 'transform_matrix' with a rigid rotation";
  if (!value.is_array() || (value.size() != 4 && value.size() != 3))
    throw std::runtime_error(
        fmt::format("{}: transform_matrix must be 4 (or 3) rows of 4 numbers{}", where, fix));
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (size_t r = 0; r < value.size(); ++r) {
    const json& row = value[r];
    if (!row.is_array() || row.size() != 4)
      throw std::runtime_error(
          fmt::format("{}: transform_matrix row {} must have 4 numbers{}", where, r, fix));
    for (size_t c = 0; c < 4; ++c) {
      if (!row[c].is_number())
        throw std::runtime_error(fmt::format("{}: transform_matrix[{}][{}] is not a number ({}){}", where, r,
                                             c, row[c].dump(), fix));
      m(r, c) = row[c].get<double>();
      if (!std::isfinite(m(r, c)))
        throw std::runtime_error(
            fmt::format("{}: transform_matrix[{}][{}] is NaN or infinite{}", where, r, c, fix));
    }
  }
  Eigen::Matrix3d rot = m.topLeftCorner<3, 3>();
  double ortho = (rot.transpose() * rot - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  // 1e-3: poses written in float32 by COLMAP/nerfstudio/Blender are orthonormal to ~1e-6; a scaled
  // or sheared matrix is off by far more.
  if (ortho > 1e-3 || rot.determinant() < 0)
    throw std::runtime_error(
        fmt::format("{}: transform_matrix is not a rigid transform (rotation deviates from orthonormal by "
                    "{:.3g}, det {:.4f}){}",
                    where, ortho, rot.determinant(), fix));
  if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6)
    throw std::runtime_error(fmt::format("{}: transform_matrix bottom row must be 0 0 0 1{}", where, fix));
  return m;
}

std::vector<FrameSpec> parse_frames(const json& doc, const std::string& json_path, Split split) {
  std::string file = fs::path(json_path).filename().string();
  if (!doc.is_object())
    throw std::runtime_error(fmt::format("'{}' must hold a JSON object with a 'frames' list", json_path));
  auto frames = doc.find("frames");
  if (frames == doc.end() || !frames->is_array())
    throw std::runtime_error(fmt::format("'{}' has no 'frames' list; is this a transforms.json?", json_path));
  if (frames->empty())
    throw std::runtime_error(
        fmt::format("'{}' has an empty 'frames' list: add at least one frame", json_path));
  DeclaredIntrinsics shared = parse_intrinsics(doc, {}, file);
  std::string dir = fs::path(json_path).parent_path().string();
  std::vector<FrameSpec> out;
  for (size_t i = 0; i < frames->size(); ++i) {
    const json& f = (*frames)[i];
    FrameSpec s;
    s.where = fmt::format("frame {} of {}", i, file);
    if (!f.is_object() || !f.contains("file_path") || !f["file_path"].is_string())
      throw std::runtime_error(fmt::format("{}: needs a 'file_path' string", s.where));
    s.file_path = f["file_path"].get<std::string>();
    s.where = fmt::format("frame {} ('{}') of {}", i, s.file_path, file);
    if (!f.contains("transform_matrix"))
      throw std::runtime_error(fmt::format("{}: has no 'transform_matrix'", s.where));
    s.c2w = parse_pose(f["transform_matrix"], s.where);
    s.intrinsics = parse_intrinsics(f, shared, s.where);
    s.split = split;
    s.image_path = resolve_image_path(dir, s.file_path);
    if (auto m = f.find("mask_path"); m != f.end() && !m->is_null()) {
      if (!m->is_string() || m->get<std::string>().empty())
        throw std::runtime_error(fmt::format(
            "{}: 'mask_path' must name a mask image (a non-empty string), found {}", s.where, m->dump()));
      s.mask_file_path = m->get<std::string>();
      s.mask_path = resolve_image_path(dir, s.mask_file_path);
    }
    out.push_back(std::move(s));
  }
  return out;
}

void check_masks_all_or_none(const std::vector<FrameSpec>& frames, const std::string& json_path) {
  size_t with = 0;
  for (const auto& f : frames) with += !f.mask_file_path.empty();
  if (with == 0 || with == frames.size()) return;
  for (const auto& f : frames)
    if (f.mask_file_path.empty())
      throw std::runtime_error(
          fmt::format("'{}': {} of {} frames have a 'mask_path' but {} has none: give every frame a mask "
                      "(0 = background) or remove 'mask_path' from all of them",
                      json_path, with, frames.size(), f.where));
}

void check_not_degenerate(const std::vector<FrameSpec>& frames) {
  if (frames.size() < 2) return;
  Eigen::Vector3d lo = frames[0].c2w.block<3, 1>(0, 3), hi = lo;
  for (const auto& f : frames) {
    lo = lo.cwiseMin(f.c2w.block<3, 1>(0, 3));
    hi = hi.cwiseMax(f.c2w.block<3, 1>(0, 3));
  }
  // Relative to the distance from the origin so that both tiny and large scenes are judged alike.
  double spread = (hi - lo).norm(), scale = std::max(1.0, lo.cwiseAbs().maxCoeff());
  if (spread <= 1e-6 * scale)
    throw std::runtime_error(fmt::format(
        "all {} cameras are at the same position ({:.6g}, {:.6g}, {:.6g}): a NeRF needs views from different "
        "positions (check that the poses were exported, not left at identity)",
        frames.size(), lo.x(), lo.y(), lo.z()));
}

std::string resolve_image_path(const std::string& dir, const std::string& file_path) {
  fs::path p = fs::path(file_path).is_absolute() ? fs::path(file_path) : fs::path(dir) / file_path;
  std::error_code ec;
  if (fs::is_regular_file(p, ec)) return fs::absolute(p).lexically_normal().string();
  if (!p.has_extension() || p.extension() == ".") {
    for (const char* ext : {".png", ".jpg", ".jpeg", ".exr", ".PNG", ".JPG", ".JPEG"}) {
      fs::path q = p;
      q += ext;
      if (fs::is_regular_file(q, ec)) return fs::absolute(q).lexically_normal().string();
    }
  }
  return "";
}

Camera make_camera(const FrameSpec& spec, int width, int height) {
  const DeclaredIntrinsics& d = spec.intrinsics;
  if ((d.w && *d.w != width) || (d.h && *d.h != height))
    throw std::runtime_error(
        fmt::format("{}: image '{}' is {}x{} but the json declares w={} h={}; fix 'w'/'h' (and the "
                    "intrinsics) or resize the "
                    "image",
                    spec.where, spec.image_path, width, height, d.w ? *d.w : width, d.h ? *d.h : height));
  Camera cam{};
  if (d.fl_x)
    cam.fx = static_cast<float>(*d.fl_x);
  else if (d.angle_x)
    cam.fx = static_cast<float>(0.5 * width / std::tan(0.5 * *d.angle_x));
  else
    throw std::runtime_error(
        fmt::format("{}: no focal length: add 'fl_x' (pixels) or 'camera_angle_x' (radians)", spec.where));
  if (d.fl_y)
    cam.fy = static_cast<float>(*d.fl_y);
  else if (d.angle_y && !d.fl_x)
    cam.fy = static_cast<float>(0.5 * height / std::tan(0.5 * *d.angle_y));
  else
    cam.fy = cam.fx;  // square pixels
  cam.cx = static_cast<float>(d.cx ? *d.cx : 0.5 * width);
  cam.cy = static_cast<float>(d.cy ? *d.cy : 0.5 * height);
  cam.k1 = static_cast<float>(d.k1);
  cam.k2 = static_cast<float>(d.k2);
  cam.p1 = static_cast<float>(d.p1);
  cam.p2 = static_cast<float>(d.p2);
  cam.width = static_cast<lgn_uint>(width);
  cam.height = static_cast<lgn_uint>(height);
  if (cam.cx < 0 || cam.cx > width || cam.cy < 0 || cam.cy > height)
    throw std::runtime_error(
        fmt::format("{}: principal point ({}, {}) lies outside the {}x{} image '{}': the intrinsics are "
                    "probably for another "
                    "resolution; fix cx/cy (and fl_x/fl_y) in the json",
                    spec.where, cam.cx, cam.cy, width, height, spec.image_path));
  set_camera_pose(cam, spec.c2w);
  return cam;
}

}  // namespace lorgnette::dataset::detail
