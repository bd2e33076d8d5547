// COLMAP's binary model layout (cameras.bin, images.bin, points3D.bin) as written by COLMAP 3.x
// (src/base/reconstruction.cc): little-endian fixed-width records, counts as uint64, image names
// NUL-terminated. Every read is bounds-checked so a truncated file gives a clear error.
#include <fmt/format.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "capture/colmap_model_io.h"

namespace lorgnette::capture {
namespace {

static_assert(sizeof(double) == 8, "COLMAP binary files store IEEE doubles");

class Reader {
 public:
  Reader(std::string data, std::string name) : path_(std::move(name)), data_(std::move(data)) {}
  template <class T>
  T get() {
    T v;
    need(sizeof(T));
    std::memcpy(&v, data_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string get_string() {
    size_t end = pos_;
    while (end < data_.size() && data_[end] != '\0') ++end;
    if (end == data_.size()) fail("unterminated image name");
    std::string s(data_.data() + pos_, end - pos_);
    pos_ = end + 1;
    return s;
  }
  // Guards counts against corrupt headers before reserving memory.
  uint64_t get_count(size_t min_record_bytes) {
    auto n = get<uint64_t>();
    if (min_record_bytes > 0 && n > (data_.size() - pos_) / min_record_bytes)
      fail(fmt::format("count {} does not fit in the file", n));
    return n;
  }
  void expect_end() const {
    if (pos_ != data_.size()) fail(fmt::format("{} unexpected trailing bytes", data_.size() - pos_));
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(fmt::format("COLMAP file '{}' is corrupt at byte {}: {}", path_, pos_, what));
  }

 private:
  void need(size_t n) const {
    if (data_.size() - pos_ < n) fail("truncated record");
  }
  std::string path_;
  std::string data_;
  size_t pos_ = 0;
};

class Writer {
 public:
  template <class T>
  void put(const T& v) {
    const char* p = reinterpret_cast<const char*>(&v);
    data_.insert(data_.end(), p, p + sizeof(T));
  }
  void put_string(const std::string& s) {
    data_.insert(data_.end(), s.begin(), s.end());
    data_.push_back('\0');
  }
  void save(const std::filesystem::path& path) const {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(data_.data(), static_cast<std::streamsize>(data_.size()));
    if (!f) throw std::runtime_error(fmt::format("cannot write COLMAP file '{}'", path.string()));
  }

 private:
  std::vector<char> data_;
};

}  // namespace

CameraMap read_cameras_binary(const std::filesystem::path& path) {
  return parse_cameras_binary(read_colmap_file(path), path.string());
}

CameraMap parse_cameras_binary(std::string bytes, const std::string& name) {
  Reader r(std::move(bytes), name);
  CameraMap cameras;
  uint64_t n = r.get_count(24);
  for (uint64_t i = 0; i < n; ++i) {
    ColmapCamera c;
    c.id = r.get<uint32_t>();
    int model_id = r.get<int32_t>();
    try {
      c.model = colmap_camera_model_name(model_id);
    } catch (const std::exception& e) {
      r.fail(e.what());
    }
    c.width = r.get<uint64_t>();
    c.height = r.get<uint64_t>();
    c.params.resize(colmap_camera_param_count(c.model));
    for (auto& p : c.params) p = r.get<double>();
    cameras[c.id] = std::move(c);
  }
  r.expect_end();
  return cameras;
}

ImageMap read_images_binary(const std::filesystem::path& path) {
  return parse_images_binary(read_colmap_file(path), path.string());
}

ImageMap parse_images_binary(std::string bytes, const std::string& name) {
  Reader r(std::move(bytes), name);
  ImageMap images;
  uint64_t n = r.get_count(73);
  for (uint64_t i = 0; i < n; ++i) {
    ColmapImage im;
    im.id = r.get<uint32_t>();
    for (int k = 0; k < 4; ++k) im.qvec[k] = r.get<double>();
    for (int k = 0; k < 3; ++k) im.tvec[k] = r.get<double>();
    im.camera_id = r.get<uint32_t>();
    im.name = r.get_string();
    uint64_t np = r.get_count(24);
    im.xys.resize(np);
    im.point3d_ids.resize(np);
    for (uint64_t k = 0; k < np; ++k) {
      im.xys[k].x() = r.get<double>();
      im.xys[k].y() = r.get<double>();
      im.point3d_ids[k] = r.get<int64_t>();
    }
    images[im.id] = std::move(im);
  }
  r.expect_end();
  return images;
}

PointMap read_points3d_binary(const std::filesystem::path& path) {
  return parse_points3d_binary(read_colmap_file(path), path.string());
}

PointMap parse_points3d_binary(std::string bytes, const std::string& name) {
  Reader r(std::move(bytes), name);
  PointMap points;
  uint64_t n = r.get_count(51);
  for (uint64_t i = 0; i < n; ++i) {
    ColmapPoint3D p;
    p.id = r.get<uint64_t>();
    for (int k = 0; k < 3; ++k) p.xyz[k] = r.get<double>();
    for (auto& c : p.rgb) c = r.get<uint8_t>();
    p.error = r.get<double>();
    uint64_t nt = r.get_count(8);
    p.track.resize(nt);
    for (auto& t : p.track) {
      t.first = r.get<uint32_t>();
      t.second = r.get<uint32_t>();
    }
    points[p.id] = std::move(p);
  }
  r.expect_end();
  return points;
}

void write_cameras_binary(const CameraMap& cameras, const std::filesystem::path& path) {
  Writer w;
  w.put<uint64_t>(cameras.size());
  for (const auto& [id, c] : cameras) {
    if (c.params.size() != colmap_camera_param_count(c.model))
      throw std::runtime_error(fmt::format("camera {}: {} needs {} parameters, got {}", id, c.model,
                                           colmap_camera_param_count(c.model), c.params.size()));
    w.put<uint32_t>(c.id);
    w.put<int32_t>(colmap_camera_model_id(c.model));
    w.put<uint64_t>(c.width);
    w.put<uint64_t>(c.height);
    for (double p : c.params) w.put<double>(p);
  }
  w.save(path);
}

void write_images_binary(const ImageMap& images, const std::filesystem::path& path) {
  Writer w;
  w.put<uint64_t>(images.size());
  for (const auto& [id, im] : images) {
    w.put<uint32_t>(im.id);
    for (int k = 0; k < 4; ++k) w.put<double>(im.qvec[k]);
    for (int k = 0; k < 3; ++k) w.put<double>(im.tvec[k]);
    w.put<uint32_t>(im.camera_id);
    w.put_string(im.name);
    w.put<uint64_t>(im.xys.size());
    for (size_t k = 0; k < im.xys.size(); ++k) {
      w.put<double>(im.xys[k].x());
      w.put<double>(im.xys[k].y());
      w.put<int64_t>(k < im.point3d_ids.size() ? im.point3d_ids[k] : -1);
    }
  }
  w.save(path);
}

void write_points3d_binary(const PointMap& points, const std::filesystem::path& path) {
  Writer w;
  w.put<uint64_t>(points.size());
  for (const auto& [id, p] : points) {
    w.put<uint64_t>(p.id);
    for (int k = 0; k < 3; ++k) w.put<double>(p.xyz[k]);
    for (uint8_t c : p.rgb) w.put<uint8_t>(c);
    w.put<double>(p.error);
    w.put<uint64_t>(p.track.size());
    for (const auto& t : p.track) {
      w.put<uint32_t>(t.first);
      w.put<uint32_t>(t.second);
    }
  }
  w.save(path);
}

}  // namespace lorgnette::capture
