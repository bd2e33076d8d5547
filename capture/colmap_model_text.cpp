// COLMAP's text model layout (cameras.txt, images.txt, points3D.txt) as written by COLMAP 3.x:
// '#' comment lines, whitespace-separated fields; images.txt has two lines per image (the pose line
// and a possibly empty POINTS2D line). Numbers are written with 17 significant digits so a text
// round trip is exact.
#include <fmt/format.h>

#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "capture/colmap_model_io.h"

namespace lorgnette::capture {
namespace {

class LineReader {
 public:
  LineReader(const std::string& text, std::string name) : path_(std::move(name)), in_(text) {}
  // Next line that is not a comment; skip_empty=false keeps empty lines (images.txt POINTS2D).
  bool next(std::string& line, bool skip_empty = true) {
    while (std::getline(in_, line)) {
      ++number_;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (!line.empty() && line[0] == '#') continue;
      if (skip_empty && line.find_first_not_of(" \t") == std::string::npos) continue;
      return true;
    }
    return false;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(fmt::format("COLMAP file '{}' line {}: {}", path_, number_, what));
  }
  template <class T>
  T field(std::istringstream& s, const char* name) const {
    T v;
    if (!(s >> v)) fail(fmt::format("missing or malformed {}", name));
    return v;
  }

 private:
  std::string path_;
  std::istringstream in_;
  int number_ = 0;
};

std::ofstream open_out(const std::filesystem::path& path) {
  std::ofstream f(path, std::ios::trunc);
  if (!f) throw std::runtime_error(fmt::format("cannot write COLMAP file '{}'", path.string()));
  return f;
}

void check_written(std::ofstream& f, const std::filesystem::path& path) {
  f.flush();
  if (!f) throw std::runtime_error(fmt::format("cannot write COLMAP file '{}'", path.string()));
}

}  // namespace

CameraMap read_cameras_text(const std::filesystem::path& path) {
  return parse_cameras_text(read_colmap_file(path), path.string());
}

CameraMap parse_cameras_text(const std::string& text, const std::string& name) {
  LineReader r(text, name);
  CameraMap cameras;
  std::string line;
  while (r.next(line)) {
    std::istringstream s(line);
    ColmapCamera c;
    c.id = r.field<uint32_t>(s, "CAMERA_ID");
    c.model = r.field<std::string>(s, "MODEL");
    c.width = r.field<uint64_t>(s, "WIDTH");
    c.height = r.field<uint64_t>(s, "HEIGHT");
    size_t count = 0;
    try {
      count = colmap_camera_param_count(c.model);
    } catch (const std::exception& e) {
      r.fail(e.what());
    }
    for (size_t k = 0; k < count; ++k) c.params.push_back(r.field<double>(s, "PARAMS"));
    cameras[c.id] = std::move(c);
  }
  return cameras;
}

ImageMap read_images_text(const std::filesystem::path& path) {
  return parse_images_text(read_colmap_file(path), path.string());
}

ImageMap parse_images_text(const std::string& text, const std::string& name) {
  LineReader r(text, name);
  ImageMap images;
  std::string line;
  while (r.next(line)) {
    std::istringstream s(line);
    ColmapImage im;
    im.id = r.field<uint32_t>(s, "IMAGE_ID");
    for (int k = 0; k < 4; ++k) im.qvec[k] = r.field<double>(s, "QVEC");
    for (int k = 0; k < 3; ++k) im.tvec[k] = r.field<double>(s, "TVEC");
    im.camera_id = r.field<uint32_t>(s, "CAMERA_ID");
    // Names may contain spaces: the rest of the line, trimmed.
    std::string rest;
    std::getline(s, rest);
    size_t b = rest.find_first_not_of(" \t"), e = rest.find_last_not_of(" \t");
    if (b == std::string::npos) r.fail("missing NAME");
    im.name = rest.substr(b, e - b + 1);
    if (!r.next(line, false)) r.fail(fmt::format("image {} has no POINTS2D line", im.id));
    std::istringstream p(line);
    double x, y;
    int64_t id;
    while (p >> x) {
      if (!(p >> y >> id)) r.fail("malformed POINTS2D triple");
      im.xys.emplace_back(x, y);
      im.point3d_ids.push_back(id);
    }
    images[im.id] = std::move(im);
  }
  return images;
}

PointMap read_points3d_text(const std::filesystem::path& path) {
  return parse_points3d_text(read_colmap_file(path), path.string());
}

PointMap parse_points3d_text(const std::string& text, const std::string& name) {
  LineReader r(text, name);
  PointMap points;
  std::string line;
  while (r.next(line)) {
    std::istringstream s(line);
    ColmapPoint3D p;
    p.id = r.field<uint64_t>(s, "POINT3D_ID");
    for (int k = 0; k < 3; ++k) p.xyz[k] = r.field<double>(s, "XYZ");
    for (auto& c : p.rgb) {
      int v = r.field<int>(s, "RGB");
      if (v < 0 || v > 255) r.fail("RGB out of 0..255");
      c = static_cast<uint8_t>(v);
    }
    p.error = r.field<double>(s, "ERROR");
    uint32_t image_id, idx;
    while (s >> image_id) {
      if (!(s >> idx)) r.fail("malformed TRACK pair");
      p.track.emplace_back(image_id, idx);
    }
    points[p.id] = std::move(p);
  }
  return points;
}

void write_cameras_text(const CameraMap& cameras, const std::filesystem::path& path) {
  auto f = open_out(path);
  f << "# Camera list with one line of data per camera:\n"
       "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
    << fmt::format("# Number of cameras: {}\n", cameras.size());
  for (const auto& [id, c] : cameras) {
    f << fmt::format("{} {} {} {}", c.id, c.model, c.width, c.height);
    for (double p : c.params) f << fmt::format(" {:.17g}", p);
    f << "\n";
  }
  check_written(f, path);
}

void write_images_text(const ImageMap& images, const std::filesystem::path& path) {
  auto f = open_out(path);
  f << "# Image list with two lines of data per image:\n"
       "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
       "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
    << fmt::format("# Number of images: {}\n", images.size());
  for (const auto& [id, im] : images) {
    f << fmt::format("{} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {} {}\n", im.id, im.qvec[0],
                     im.qvec[1], im.qvec[2], im.qvec[3], im.tvec[0], im.tvec[1], im.tvec[2], im.camera_id,
                     im.name);
    for (size_t k = 0; k < im.xys.size(); ++k)
      f << fmt::format("{}{:.17g} {:.17g} {}", k ? " " : "", im.xys[k].x(), im.xys[k].y(),
                       k < im.point3d_ids.size() ? im.point3d_ids[k] : -1);
    f << "\n";
  }
  check_written(f, path);
}

void write_points3d_text(const PointMap& points, const std::filesystem::path& path) {
  auto f = open_out(path);
  f << "# 3D point list with one line of data per point:\n"
       "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
    << fmt::format("# Number of points: {}\n", points.size());
  for (const auto& [id, p] : points) {
    f << fmt::format("{} {:.17g} {:.17g} {:.17g} {} {} {} {:.17g}", p.id, p.xyz[0], p.xyz[1], p.xyz[2],
                     p.rgb[0], p.rgb[1], p.rgb[2], p.error);
    for (const auto& t : p.track) f << fmt::format(" {} {}", t.first, t.second);
    f << "\n";
  }
  check_written(f, path);
}

}  // namespace lorgnette::capture
