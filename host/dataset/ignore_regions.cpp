// ignore_regions.json; see ignore_regions.h.
#include "host/dataset/ignore_regions.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>

#include "host/util/image_io.h"

namespace lorgnette::dataset {
namespace {

constexpr int kFormatVersion = 1;

IgnorePolygon parse_polygon(const nlohmann::json& j) {
  IgnorePolygon poly;
  for (const auto& v : j.get<std::vector<std::vector<float>>>()) {
    if (v.size() != 2)
      throw std::runtime_error(fmt::format("a vertex has {} numbers, not 2 (x, y)", v.size()));
    poly.emplace_back(v[0], v[1]);
  }
  return poly;
}

nlohmann::json polygon_json(const IgnorePolygon& poly) {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& v : poly) j.push_back({v.x(), v.y()});
  return j;
}

FrameIgnore parse_frame(const nlohmann::json& j) {
  FrameIgnore f;
  f.name = j.at("name").get<std::string>();
  f.width = j.at("width").get<int>();
  f.height = j.at("height").get<int>();
  for (const auto& p : j.at("polygons")) f.polygons.push_back(parse_polygon(p));
  return f;
}

}  // namespace

void check_ignore_regions(const IgnoreRegions& r, const std::string& where) {
  if (r.source.empty())
    throw std::runtime_error(fmt::format("{}: source must name what the regions hide", where));
  if (!(std::isfinite(r.margin_mm) && r.margin_mm >= 0))
    throw std::runtime_error(
        fmt::format("{}: margin_mm must be a number >= 0, found {}", where, r.margin_mm));
  std::set<std::string> names;
  for (const FrameIgnore& f : r.frames) {
    if (f.name.empty()) throw std::runtime_error(fmt::format("{}: a frame has an empty name", where));
    if (!names.insert(f.name).second)
      throw std::runtime_error(fmt::format("{}: frame '{}' is listed twice", where, f.name));
    if (f.width <= 0 || f.height <= 0)
      throw std::runtime_error(fmt::format("{}: frame '{}' has image size {}x{}; both must be positive",
                                           where, f.name, f.width, f.height));
    for (const IgnorePolygon& p : f.polygons) {
      if (p.size() < 3)
        throw std::runtime_error(fmt::format(
            "{}: frame '{}' has a polygon of {} vertices; at least 3 are needed", where, f.name, p.size()));
      for (const auto& v : p)
        if (!v.allFinite())
          throw std::runtime_error(
              fmt::format("{}: frame '{}' has a vertex that is not a finite number", where, f.name));
    }
  }
}

void write_ignore_regions(const std::string& dataset_dir, const IgnoreRegions& r) {
  check_ignore_regions(r, kIgnoreRegionsFile);
  nlohmann::json frames = nlohmann::json::array();
  for (const FrameIgnore& f : r.frames) {
    nlohmann::json polys = nlohmann::json::array();
    for (const auto& p : f.polygons) polys.push_back(polygon_json(p));
    frames.push_back({{"name", f.name}, {"width", f.width}, {"height", f.height}, {"polygons", polys}});
  }
  const nlohmann::json j = {
      {"version", kFormatVersion}, {"source", r.source}, {"margin_mm", r.margin_mm}, {"frames", frames}};
  write_text_file_atomic((std::filesystem::path(dataset_dir) / kIgnoreRegionsFile).string(),
                         j.dump(1) + "\n");
}

std::optional<IgnoreRegions> read_ignore_regions(const std::string& dataset_dir) {
  const std::filesystem::path p = std::filesystem::path(dataset_dir) / kIgnoreRegionsFile;
  if (!std::filesystem::exists(p)) return std::nullopt;
  const std::string where = fmt::format("'{}'", p.string());
  const std::string advice =
      "fix it, run `lorgnette capture --card-only` on the dataset again, or delete it (training then uses "
      "every pixel of every frame)";
  auto bad = [&](const std::string& what) {
    return std::runtime_error(fmt::format("{} {}; {}", where, what, advice));
  };
  std::ifstream in(p);
  if (!in) throw bad("cannot be read");
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw bad("is not a JSON object");
  const auto version = j.find("version");
  if (version == j.end() || !version->is_number_integer() || version->get<int>() != kFormatVersion)
    throw bad(fmt::format("has format version {}; this build reads version {}",
                          version == j.end() ? "(none)" : version->dump(), kFormatVersion));
  IgnoreRegions r;
  try {
    r.source = j.at("source").get<std::string>();
    r.margin_mm = j.value("margin_mm", 0.0);
    for (const auto& f : j.at("frames")) r.frames.push_back(parse_frame(f));
  } catch (const nlohmann::json::exception& e) {
    throw bad(fmt::format("lacks a field or has one of the wrong type ({})", e.what()));
  } catch (const std::runtime_error& e) {
    throw bad(e.what());
  }
  try {
    check_ignore_regions(r, where);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(fmt::format("{}; {}", e.what(), advice));
  }
  return r;
}

std::vector<IgnorePolygon> scale_polygons(const std::vector<IgnorePolygon>& polygons, int from_w, int from_h,
                                          int to_w, int to_h) {
  const float sx = float(to_w) / float(from_w), sy = float(to_h) / float(from_h);
  std::vector<IgnorePolygon> out = polygons;
  for (auto& p : out)
    for (auto& v : p) v = Eigen::Vector2f(v.x() * sx, v.y() * sy);
  return out;
}

}  // namespace lorgnette::dataset
