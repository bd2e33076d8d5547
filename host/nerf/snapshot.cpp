// The model's host-side data and the .lnerf snapshot format (see snapshot.h). Parsing checks every
// header value's type and range itself: nlohmann's get<T>() casts an out-of-range number silently
// (undefined behaviour for floats), and a corrupt file must get a clear message, not a crash.
#include "host/nerf/snapshot.h"

#include <fmt/format.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "host/nerf/blob_table.h"
#include "host/util/bounds.h"
#include "host/util/file_kind.h"
#include "kernels/train/occupancy.h"

namespace lorgnette::nerf {
namespace {

using nlohmann::json;

constexpr char kMagic[9] = "LGNNERF\n";

uint64_t fnv1a64_bytes(const void* data, size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  uint64_t h = 1469598103934665603ull;
  for (size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

// Where the header checksum's 16 hex digits start in the header text, or npos. Inside a JSON string
// every quote is escaped, so the key's pattern can only match the key itself.
size_t checksum_digits(std::string_view header) {
  const std::string pattern = fmt::format("\"{}\":\"", kHeaderChecksumKey);
  size_t at = header.find(pattern);
  if (at == std::string_view::npos || header.size() - (at + pattern.size()) < 16)
    return std::string_view::npos;
  return at + pattern.size();
}

// The checksum of `header` with its checksum digits (at `digits`) read as '0'.
std::string header_checksum(std::string_view header, size_t digits) {
  std::string zeroed(header);
  zeroed.replace(digits, 16, 16, '0');
  return checksum_hex(fnv1a64_bytes(zeroed.data(), zeroed.size()));
}

[[noreturn]] void corrupt(const std::string& path, const std::string& why) {
  throw std::runtime_error("model file '" + path + "' is corrupt or not a Lorgnette model (" + why +
                           "): retrain it or use another file");
}

// Thrown by the checked getters inside the header parse; turned into corrupt("bad header: ...").
struct BadValue : std::runtime_error {
  using std::runtime_error::runtime_error;
};

uint64_t to_uint(const json& j, const std::string& what, uint64_t max = UINT64_MAX) {
  if (!j.is_number_unsigned() || j.get<uint64_t>() > max)
    throw BadValue(fmt::format("'{}' must be an integer in 0..{}, found {}", what, max, j.dump()));
  return j.get<uint64_t>();
}

double to_double(const json& j, const std::string& what, double max = DBL_MAX) {
  double v = j.is_number() ? j.get<double>() : NAN;
  if (!std::isfinite(v) || std::abs(v) > max)
    throw BadValue(fmt::format("'{}' must be a finite number, found {}", what, j.dump()));
  return v;
}

float to_float(const json& j, const std::string& what) {
  return static_cast<float>(to_double(j, what, double(FLT_MAX)));
}

std::array<float, 3> to_float3(const json& j, const std::string& what) {
  if (!j.is_array() || j.size() != 3)
    throw BadValue(fmt::format("'{}' must be 3 numbers, found {}", what, j.dump()));
  return {to_float(j[0], what), to_float(j[1], what), to_float(j[2], what)};
}

// The value under `key` of object `j`, or nullptr when it is absent or null (the default applies).
const json* optional(const json& j, const char* key) {
  auto it = j.find(key);
  return it == j.end() || it->is_null() ? nullptr : &*it;
}

json metadata_json(const ModelMetadata& m) {
  json j = {{"steps", m.steps},
            {"train_seconds", m.train_seconds},
            {"samples_trained", m.samples_trained},
            {"seed", m.seed},
            {"final_loss", m.final_loss},
            {"dataset_path", m.dataset_path},
            {"dataset_hash", m.dataset_hash},
            {"device", m.device},
            {"created", m.created},
            {"subject_problem", m.subject_problem},
            {"holes", m.holes},
            {"holes_worst_view", m.holes_worst_view}};
  if (m.metric_scale)
    j["metric_scale"] = {{"source", m.metric_scale->source},
                         {"mm_per_unit", m.metric_scale->mm_per_unit},
                         {"mm_per_unit_uncertainty", m.metric_scale->uncertainty}};
  return j;
}

// Absent (files written before it, or no scale measured): unknown.
MetricScale metric_scale_from_json(const json& j) {
  if (!j.is_object()) throw BadValue("'metadata.metric_scale' must be an object, found " + j.dump());
  MetricScale s;
  auto* src = optional(j, "source");
  if (!src || !src->is_string() || src->get<std::string>().empty())
    throw BadValue("'metadata.metric_scale.source' must name where the scale came from, found " +
                   (src ? src->dump() : std::string("nothing")));
  s.source = src->get<std::string>();
  auto* mm = optional(j, "mm_per_unit");
  s.mm_per_unit = mm ? to_double(*mm, "metadata.metric_scale.mm_per_unit") : 0.0;
  if (!(s.mm_per_unit > 0))
    throw BadValue(
        fmt::format("'metadata.metric_scale.mm_per_unit' must be positive, found {}", s.mm_per_unit));
  if (auto* u = optional(j, "mm_per_unit_uncertainty"))
    s.uncertainty = to_double(*u, "metadata.metric_scale.mm_per_unit_uncertainty");
  if (s.uncertainty < 0)
    throw BadValue(
        fmt::format("'metadata.metric_scale.mm_per_unit_uncertainty' must be >= 0, found {}", s.uncertainty));
  return s;
}

ModelMetadata metadata_from_json(const json& j) {
  if (!j.is_object()) throw BadValue("'metadata' must be an object, found " + j.dump());
  ModelMetadata m;
  if (auto* v = optional(j, "steps")) m.steps = to_uint(*v, "metadata.steps");
  if (auto* v = optional(j, "train_seconds")) m.train_seconds = to_double(*v, "metadata.train_seconds");
  if (auto* v = optional(j, "samples_trained")) m.samples_trained = to_uint(*v, "metadata.samples_trained");
  if (auto* v = optional(j, "seed")) m.seed = to_uint(*v, "metadata.seed");
  // A diverged training run saves a NaN loss, which JSON writes as null.
  if (j.contains("final_loss"))
    m.final_loss = j["final_loss"].is_null() ? NAN : to_float(j["final_loss"], "metadata.final_loss");
  m.dataset_path = j.value("dataset_path", "");
  m.dataset_hash = j.value("dataset_hash", "");
  m.device = j.value("device", "");
  m.created = j.value("created", "");
  if (auto* v = optional(j, "subject_problem")) {
    if (!v->is_string()) throw BadValue("'metadata.subject_problem' must be a string, found " + v->dump());
    m.subject_problem = v->get<std::string>();
  }
  // Absent in files written before the hole check: not checked.
  if (auto* v = optional(j, "holes")) m.holes = to_double(*v, "metadata.holes", 1.0);
  if (auto* v = optional(j, "holes_worst_view"))
    m.holes_worst_view = to_double(*v, "metadata.holes_worst_view", 1.0);
  if (auto* v = optional(j, "metric_scale")) m.metric_scale = metric_scale_from_json(*v);
  return m;
}

SceneNormalisation normalisation_from_json(const json& j, const std::string& path) {
  if (!j.is_object()) throw BadValue("'normalisation' must be an object, found " + j.dump());
  SceneNormalisation n;
  if (auto* v = optional(j, "scale")) n.scale = to_float(*v, "normalisation.scale");
  if (auto* v = optional(j, "offset")) n.offset = to_float3(*v, "normalisation.offset");
  check_file_bound(path, bounds::kNormalisationScale, n.scale);
  for (float o : n.offset) check_file_bound(path, bounds::kNormalisationOffset, o);
  return n;
}

nlohmann::json view_range_json(const ViewRange& r) {
  return {{"center", r.center},
          {"front", r.front},
          {"up", r.up},
          {"yaw_deg", {r.yaw_min, r.yaw_max}},
          {"pitch_deg", {r.pitch_min, r.pitch_max}},
          {"cameras", r.cameras}};
}

std::array<double, 2> to_interval(const json& j, const std::string& what, double bound) {
  if (!j.is_array() || j.size() != 2)
    throw BadValue(fmt::format("'{}' must be [min, max], found {}", what, j.dump()));
  std::array<double, 2> v{to_double(j[0], what, bound), to_double(j[1], what, bound)};
  if (v[0] > v[1]) throw BadValue(fmt::format("'{}' has min > max: {}", what, j.dump()));
  return v;
}

ViewRange view_range_from_json(const json& j) {
  if (!j.is_object()) throw BadValue("'view_range' must be an object, found " + j.dump());
  ViewRange r;
  r.center = to_float3(j.at("center"), "view_range.center");
  r.front = to_float3(j.at("front"), "view_range.front");
  r.up = to_float3(j.at("up"), "view_range.up");
  auto yaw = to_interval(j.at("yaw_deg"), "view_range.yaw_deg", 180.0);
  auto pitch = to_interval(j.at("pitch_deg"), "view_range.pitch_deg", 90.0);
  r.yaw_min = yaw[0], r.yaw_max = yaw[1], r.pitch_min = pitch[0], r.pitch_max = pitch[1];
  r.cameras = static_cast<uint32_t>(to_uint(j.at("cameras"), "view_range.cameras", UINT32_MAX));
  if (!r.valid()) throw BadValue("'view_range' axes must be unit length and orthogonal, found " + j.dump());
  return r;
}

// The header's values, checked; the blob table is left to parse_blobs.
void parse_header(const json& h, const std::string& path, Snapshot& s) {
  if (!h.is_object()) corrupt(path, "the header is not a JSON object");
  uint64_t version = to_uint(h.at("version"), "version");
  if (version > kSnapshotVersion)
    throw std::runtime_error(
        fmt::format("model file '{}' has format version {}, newer than this build reads (up to {}): update "
                    "Lorgnette or retrain the model with this version",
                    path, version, kSnapshotVersion));
  if (h.value("format", "") != "lorgnette-nerf") corrupt(path, "header format is not lorgnette-nerf");
  s.config = field::FieldConfig::from_json(h.at("field"));
  s.config.validate();
  s.aabb.min = to_float3(h.at("aabb").at("min"), "aabb.min");
  s.aabb.max = to_float3(h.at("aabb").at("max"), "aabb.max");
  s.step = to_float(h.at("step"), "step");
  s.occ.res = static_cast<uint32_t>(to_uint(h.at("occupancy").at("res"), "occupancy.res", UINT32_MAX));
  if (auto* v = optional(h, "normalisation")) s.normalisation = normalisation_from_json(*v, path);
  if (auto* v = optional(h, "metadata")) s.metadata = metadata_from_json(*v);
  if (auto* v = optional(h, "view_range")) s.view_range = view_range_from_json(*v);
}

// Version 2 on: the header's own checksum (seal_header) must match its bytes, so a flipped bit in a
// value that still parses (the box, the step, the normalisation) is refused, not used.
void check_header_checksum(const json& h, std::string_view text, const std::string& path) {
  if (h.at("version").get<uint64_t>() < 2) return;  // version 1 headers carry none
  auto it = h.find(kHeaderChecksumKey);
  size_t digits = checksum_digits(text);
  if (it == h.end() || !it->is_string() || digits == std::string_view::npos)
    corrupt(path, fmt::format("the header has no '{}' checksum", kHeaderChecksumKey));
  std::string stored(text.substr(digits, 16));
  if (it->get<std::string>() != stored || header_checksum(text, digits) != stored)
    corrupt(path, "checksum mismatch in the header (a changed or damaged byte in its box, step or settings)");
}

// The box inside kSceneCoord and a step that gives a sane number of steps across it (bounds.h).
void check_box_and_step(const Snapshot& s, const std::string& path) {
  if (!s.aabb.valid()) corrupt(path, "invalid bounding box");
  for (int a = 0; a < 3; ++a)
    if (std::abs(s.aabb.min[a]) > bounds::kSceneCoord || std::abs(s.aabb.max[a]) > bounds::kSceneCoord)
      corrupt(path, fmt::format("the bounding box reaches beyond +-{:g} scene units", bounds::kSceneCoord));
  if (!(s.step > 0.0f)) corrupt(path, "invalid step size");
  try {
    check_steps_per_diagonal(s.aabb.diagonal(), s.step, "step");
  } catch (const OutOfRange& e) {
    corrupt(path, e.what());
  }
}

// Copies the blobs out of the file into s.params and s.occ (sizes from the parsed header).
void parse_blobs(const json& h, const std::string& path, std::string_view file, size_t start, Snapshot& s) {
  bool has_density = h.at("occupancy").value("has_density", false);
  const json& blobs = h.at("blobs");
  size_t n_params = s.config.param_count(), n_words = occ_word_count(s.occ.res);
  size_t n_cells = size_t(s.occ.res) * s.occ.res * s.occ.res;
  const char *p = nullptr, *w = nullptr, *d = nullptr;
  try {
    p = find_blob(file, start, blobs, "params", n_params * 4);
    w = find_blob(file, start, blobs, "occupancy_bits", n_words * 4);
    d = find_blob(file, start, blobs, "occupancy_density", has_density ? n_cells * 4 : 0);
  } catch (const BlobTableError& e) {
    corrupt(path, e.what());
  }
  s.params.resize(n_params);
  std::memcpy(s.params.data(), p, n_params * 4);
  s.occ.bits.resize(n_words);
  std::memcpy(s.occ.bits.data(), w, n_words * 4);
  if (d) {
    s.occ.density.resize(n_cells);
    std::memcpy(s.occ.density.data(), d, n_cells * 4);
  }
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

std::string encode_snapshot(const Snapshot& s) {
  std::vector<BlobRef> blobs = {{"params", s.params.data(), s.params.size() * 4},
                                {"occupancy_bits", s.occ.bits.data(), s.occ.bits.size() * 4}};
  if (!s.occ.density.empty())
    blobs.push_back({"occupancy_density", s.occ.density.data(), s.occ.density.size() * 4});
  json header = {{"format", "lorgnette-nerf"},
                 {"version", kSnapshotVersion},
                 {"field", s.config.to_json()},
                 {"aabb", {{"min", s.aabb.min}, {"max", s.aabb.max}}},
                 {"step", s.step},
                 {"occupancy", {{"res", s.occ.res}, {"has_density", !s.occ.density.empty()}}},
                 {"normalisation", {{"scale", s.normalisation.scale}, {"offset", s.normalisation.offset}}},
                 {"metadata", metadata_json(s.metadata)}};
  if (s.view_range) header["view_range"] = view_range_json(*s.view_range);
  header[kHeaderChecksumKey] = std::string(16, '0');
  header["blobs"] = blob_table(blobs);
  std::string text = seal_header(header.dump());
  std::string out(kMagic, 8);
  uint64_t hlen = text.size();
  out.append(reinterpret_cast<const char*>(&hlen), 8);
  out += text;
  append_blobs(out, blobs);
  return out;
}

Snapshot parse_snapshot(std::string_view file, const std::string& path) {
  if (file.size() < 16 || std::memcmp(file.data(), kMagic, 8) != 0) corrupt(path, "bad magic bytes");
  uint64_t hlen = 0;
  std::memcpy(&hlen, file.data() + 8, 8);
  if (hlen > file.size() - 16) corrupt(path, "header length exceeds the file size");
  Snapshot s;
  json header;
  try {
    header = json::parse(file.substr(16, hlen));
    parse_header(header, path, s);
  } catch (const json::exception& e) {
    corrupt(path, std::string("bad header: ") + e.what());
  } catch (const BadValue& e) {
    corrupt(path, std::string("bad header: ") + e.what());
  } catch (const OutOfRange& e) {
    corrupt(path, std::string("bad header: ") + e.what());
  } catch (const std::invalid_argument& e) {
    corrupt(path, std::string("bad field configuration: ") + e.what());
  }
  check_box_and_step(s, path);
  if (s.occ.res < 1 || s.occ.res > 1024) corrupt(path, "invalid occupancy resolution");
  try {
    parse_blobs(header, path, file, 16 + hlen, s);
  } catch (const json::exception& e) {
    corrupt(path, std::string("bad header: ") + e.what());
  } catch (const BadValue& e) {
    corrupt(path, std::string("bad header: ") + e.what());
  }
  // Last: every value that is out of its range or type has been named above; what is left for the
  // checksum is a change that still parses.
  check_header_checksum(header, file.substr(16, hlen), path);
  for (float v : s.params)
    if (!std::isfinite(v)) corrupt(path, "non-finite parameter values");
  return s;
}

uint64_t snapshot_checksum(std::string_view bytes) { return fnv1a64_bytes(bytes.data(), bytes.size()); }

std::string seal_header(std::string header) {
  size_t digits = checksum_digits(header);
  if (digits != std::string::npos) header.replace(digits, 16, header_checksum(header, digits));
  return header;
}

Snapshot read_snapshot(const std::string& path) {
  return parse_snapshot(read_regular_file(path, "model file"), path);
}

}  // namespace lorgnette::nerf
