// NerfModel: construction, occupancy upload, and the .lnerf snapshot format:
//   8 bytes magic "LGNNERF\n", 8 bytes little-endian header length H, H bytes of JSON header,
//   then the binary blobs the header lists (name, offset from the end of the header, bytes,
//   FNV-1a 64 checksum). Loading validates all of it before building the model.
#include "host/nerf/model.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "host/util/image_io.h"
#include "kernels/train/occupancy.h"

namespace lorgnette::nerf {
namespace {

constexpr char kMagic[9] = "LGNNERF\n";

uint64_t fnv1a64(const void* data, size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  uint64_t h = 1469598103934665603ull;
  for (size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

std::string hex64(uint64_t v) { return fmt::format("{:016x}", v); }

struct Blob {
  std::string name;
  const void* data;
  size_t bytes;
};

nlohmann::json metadata_json(const ModelMetadata& m) {
  return {{"steps", m.steps}, {"train_seconds", m.train_seconds}, {"samples_trained", m.samples_trained},
          {"seed", m.seed}, {"final_loss", m.final_loss}, {"dataset_path", m.dataset_path},
          {"dataset_hash", m.dataset_hash}, {"device", m.device}, {"created", m.created}};
}

ModelMetadata metadata_from_json(const nlohmann::json& j) {
  ModelMetadata m;
  m.steps = j.value("steps", uint64_t(0));
  m.train_seconds = j.value("train_seconds", 0.0);
  m.samples_trained = j.value("samples_trained", uint64_t(0));
  m.seed = j.value("seed", uint64_t(0));
  m.final_loss = j.value("final_loss", 0.0f);
  m.dataset_path = j.value("dataset_path", "");
  m.dataset_hash = j.value("dataset_hash", "");
  m.device = j.value("device", "");
  m.created = j.value("created", "");
  return m;
}

[[noreturn]] void corrupt(const std::string& path, const std::string& why) {
  throw std::runtime_error("model file '" + path + "' is corrupt or not a Lorgnette model (" + why +
                           "): retrain it or use another file");
}

std::vector<char> read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open model file '" + path + "': check the path");
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return bytes;
}

// Everything load() needs, parsed and checked, before any device object exists.
struct ParsedSnapshot {
  nlohmann::json header;
  field::FieldConfig config;
  Aabb aabb;
  float step = 0.0f;
  OccupancyGrid occ;
  std::vector<float> params;
};

const char* find_blob(const std::string& path, const std::vector<char>& file, size_t data_start,
                      const nlohmann::json& blobs, const std::string& name, size_t expected_bytes) {
  for (const auto& b : blobs) {
    if (b.value("name", "") != name) continue;
    uint64_t off = b.at("offset").get<uint64_t>(), bytes = b.at("bytes").get<uint64_t>();
    if (bytes != expected_bytes)
      corrupt(path, fmt::format("blob '{}' has {} bytes, the header's configuration needs {}", name, bytes,
                                expected_bytes));
    if (data_start + off + bytes > file.size() || off > file.size())
      corrupt(path, fmt::format("file is truncated: blob '{}' ends past the end of the file", name));
    const char* p = file.data() + data_start + off;
    if (hex64(fnv1a64(p, bytes)) != b.value("fnv1a64", ""))
      corrupt(path, fmt::format("checksum mismatch in blob '{}'", name));
    return p;
  }
  if (expected_bytes == 0) return nullptr;
  corrupt(path, "blob '" + name + "' is missing");
}

ParsedSnapshot parse_snapshot(const std::string& path) {
  std::vector<char> file = read_all(path);
  if (file.size() < 16 || std::memcmp(file.data(), kMagic, 8) != 0) corrupt(path, "bad magic bytes");
  uint64_t hlen = 0;
  std::memcpy(&hlen, file.data() + 8, 8);
  if (hlen > file.size() - 16) corrupt(path, "header length exceeds the file size");
  ParsedSnapshot s;
  try {
    s.header = nlohmann::json::parse(file.begin() + 16, file.begin() + 16 + static_cast<long>(hlen));
    uint32_t version = s.header.at("version").get<uint32_t>();
    if (version > kSnapshotVersion)
      throw std::runtime_error(fmt::format(
          "model file '{}' has format version {}, newer than this build reads (up to {}): update "
          "Lorgnette or retrain the model with this version", path, version, kSnapshotVersion));
    if (s.header.value("format", "") != "lorgnette-nerf") corrupt(path, "header format is not lorgnette-nerf");
    s.config = field::FieldConfig::from_json(s.header.at("field"));
    s.config.validate();
    for (int a = 0; a < 3; ++a) {
      s.aabb.min[a] = s.header.at("aabb").at("min").at(a).get<float>();
      s.aabb.max[a] = s.header.at("aabb").at("max").at(a).get<float>();
    }
    s.step = s.header.at("step").get<float>();
    s.occ.res = s.header.at("occupancy").at("res").get<uint32_t>();
  } catch (const nlohmann::json::exception& e) {
    corrupt(path, std::string("bad header: ") + e.what());
  } catch (const std::invalid_argument& e) {
    corrupt(path, std::string("bad field configuration: ") + e.what());
  }
  if (!s.aabb.valid()) corrupt(path, "invalid bounding box");
  if (!(s.step > 0.0f) || !std::isfinite(s.step)) corrupt(path, "invalid step size");
  if (s.occ.res < 1 || s.occ.res > 1024) corrupt(path, "invalid occupancy resolution");
  bool has_density = s.header.at("occupancy").value("has_density", false);
  const auto& blobs = s.header.at("blobs");
  size_t start = 16 + hlen;
  size_t n_params = s.config.param_count(), n_words = occ_word_count(s.occ.res);
  size_t n_cells = size_t(s.occ.res) * s.occ.res * s.occ.res;
  const char* p = find_blob(path, file, start, blobs, "params", n_params * 4);
  const char* w = find_blob(path, file, start, blobs, "occupancy_bits", n_words * 4);
  const char* d = find_blob(path, file, start, blobs, "occupancy_density", has_density ? n_cells * 4 : 0);
  s.params.resize(n_params);
  std::memcpy(s.params.data(), p, n_params * 4);
  s.occ.bits.resize(n_words);
  std::memcpy(s.occ.bits.data(), w, n_words * 4);
  if (d) {
    s.occ.density.resize(n_cells);
    std::memcpy(s.occ.density.data(), d, n_cells * 4);
  }
  for (float v : s.params)
    if (!std::isfinite(v)) corrupt(path, "non-finite parameter values");
  return s;
}

}  // namespace

float Aabb::max_extent() const { return std::max(extent(0), std::max(extent(1), extent(2))); }
float Aabb::diagonal() const {
  return std::sqrt(extent(0) * extent(0) + extent(1) * extent(1) + extent(2) * extent(2));
}
std::array<float, 3> Aabb::center() const {
  return {0.5f * (min[0] + max[0]), 0.5f * (min[1] + max[1]), 0.5f * (min[2] + max[2])};
}
bool Aabb::valid() const {
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(min[a]) || !std::isfinite(max[a]) || !(max[a] > min[a])) return false;
  return true;
}
std::array<float, 3> Aabb::normalise(const std::array<float, 3>& p) const {
  return {(p[0] - min[0]) / extent(0), (p[1] - min[1]) / extent(1), (p[2] - min[2]) / extent(2)};
}

uint64_t OccupancyGrid::occupied_count() const {
  uint64_t n = 0;
  for (uint32_t w : bits) n += static_cast<uint64_t>(__builtin_popcount(w));
  return n;
}
double OccupancyGrid::occupied_fraction() const {
  return double(occupied_count()) / (double(res) * res * res);
}

OccupancyGrid full_occupancy(uint32_t res) {
  OccupancyGrid g;
  g.res = res;
  uint64_t cells = uint64_t(res) * res * res;
  g.bits.assign(occ_word_count(res), 0xffffffffu);
  if (cells % 32) g.bits.back() = (1u << (cells % 32)) - 1u;
  return g;
}

NerfModel::NerfModel(cl::Runtime& rt, const field::FieldConfig& config, const Aabb& aabb, uint32_t occ_res,
                     float step, uint32_t max_batch, uint64_t seed, bool deterministic)
    : rt_(&rt),
      field_(std::make_unique<field::Field>(rt, config, max_batch, seed, deterministic)),
      aabb_(aabb),
      step_(step) {
  if (!aabb.valid()) throw std::invalid_argument("NerfModel: the bounding box must have max > min on every axis");
  if (!(step > 0.0f)) throw std::invalid_argument("NerfModel: the step size must be positive");
  if (occ_res < 1 || occ_res > 1024)
    throw std::invalid_argument(fmt::format("NerfModel: occupancy resolution {} is outside 1..1024", occ_res));
  set_occupancy(full_occupancy(occ_res));
}

uint32_t NerfModel::max_samples_per_ray() const {
  return static_cast<uint32_t>(std::ceil(aabb_.diagonal() / step_)) + 1u;
}

void NerfModel::set_occupancy(OccupancyGrid grid) {
  uint64_t cells = uint64_t(grid.res) * grid.res * grid.res;
  if (grid.bits.size() != occ_word_count(grid.res) || (!grid.density.empty() && grid.density.size() != cells))
    throw std::invalid_argument(fmt::format("occupancy grid of resolution {} needs {} words ({} given)",
                                            grid.res, occ_word_count(grid.res), grid.bits.size()));
  if (occ_bits_.size() != grid.bits.size()) occ_bits_ = cl::Buffer<uint32_t>(*rt_, grid.bits.size());
  occ_bits_.write(*rt_, grid.bits);
  occ_ = std::move(grid);
}

uint64_t NerfModel::param_bytes() const { return field_->config().bytes(); }

void NerfModel::save(const std::string& path) const {
  std::vector<float> params = field_->download_params();
  std::vector<Blob> blobs = {{"params", params.data(), params.size() * 4},
                             {"occupancy_bits", occ_.bits.data(), occ_.bits.size() * 4}};
  if (!occ_.density.empty()) blobs.push_back({"occupancy_density", occ_.density.data(), occ_.density.size() * 4});
  nlohmann::json header = {
      {"format", "lorgnette-nerf"}, {"version", kSnapshotVersion}, {"field", field_->config().to_json()},
      {"aabb", {{"min", aabb_.min}, {"max", aabb_.max}}}, {"step", step_},
      {"occupancy", {{"res", occ_.res}, {"has_density", !occ_.density.empty()}}},
      {"normalisation", {{"scale", normalisation.scale}, {"offset", normalisation.offset}}},
      {"metadata", metadata_json(metadata)}};
  uint64_t off = 0;
  for (const auto& b : blobs) {
    header["blobs"].push_back({{"name", b.name}, {"offset", off}, {"bytes", b.bytes},
                               {"fnv1a64", hex64(fnv1a64(b.data, b.bytes))}});
    off += b.bytes;
  }
  std::string text = header.dump();
  std::string out(kMagic, 8);
  uint64_t hlen = text.size();
  out.append(reinterpret_cast<const char*>(&hlen), 8);
  out += text;
  for (const auto& b : blobs) out.append(static_cast<const char*>(b.data), b.bytes);
  write_text_file_atomic(path, out);
}

NerfModel NerfModel::load(cl::Runtime& rt, const std::string& path, uint32_t max_batch, bool deterministic) {
  ParsedSnapshot s = parse_snapshot(path);
  NerfModel m(rt, s.config, s.aabb, s.occ.res, s.step, max_batch, s.header["metadata"].value("seed", 0ull),
              deterministic);
  m.field_->upload_params(s.params);
  m.set_occupancy(std::move(s.occ));
  const auto& norm = s.header.value("normalisation", nlohmann::json::object());
  m.normalisation.scale = norm.value("scale", 1.0f);
  if (norm.contains("offset")) m.normalisation.offset = norm["offset"].get<std::array<float, 3>>();
  m.metadata = metadata_from_json(s.header.value("metadata", nlohmann::json::object()));
  return m;
}

}  // namespace lorgnette::nerf
