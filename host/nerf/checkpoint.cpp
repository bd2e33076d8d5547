// The training checkpoint format (checkpoint.h): "LGNCKPT\n", the header's length (u64, little
// endian) and its FNV-1a 64 (u64), the JSON header (version, key, counters, each field's sizes and
// the blob table with each blob's FNV-1a 64), then the blobs (float32 / uint32, little endian).
#include "host/nerf/checkpoint.h"

#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "host/nerf/blob_table.h"
#include "host/util/file_write.h"
#include "kernels/train/occupancy.h"

namespace lorgnette::nerf {
namespace {

using nlohmann::json;

constexpr char kMagic[9] = "LGNCKPT\n";
constexpr size_t kPrefix = 24;  // magic, header length, header checksum

[[noreturn]] void corrupt(const std::string& path, const std::string& why) {
  throw CheckpointCorrupt(fmt::format(
      "training checkpoint '{}' is corrupt or not a Lorgnette checkpoint ({}): remove it to train from "
      "the start",
      path, why));
}

void add_field_blobs(const std::string& prefix, const FieldState& f, std::vector<BlobRef>& blobs) {
  blobs.push_back({prefix + ".params", f.params.data(), f.params.size() * 4});
  blobs.push_back({prefix + ".adam_m", f.adam.m.data(), f.adam.m.size() * 4});
  blobs.push_back({prefix + ".adam_v", f.adam.v.data(), f.adam.v.size() * 4});
  blobs.push_back({prefix + ".occupancy_bits", f.occupancy.bits.data(), f.occupancy.bits.size() * 4});
  blobs.push_back(
      {prefix + ".occupancy_density", f.occupancy.density.data(), f.occupancy.density.size() * 4});
}

json field_header(const FieldState& f) {
  return {{"params", f.params.size()},
          {"adam_t", f.adam.t},
          {"occupancy_res", f.occupancy.res},
          {"occupancy_updates", f.occupancy_updates},
          {"has_density", !f.occupancy.density.empty()}};
}

// The blob `name` (count elements of T), checked by the blob table, copied into `out`.
template <typename T>
void read_blob(const json& table, std::string_view file, size_t data_start, const std::string& name,
               size_t count, std::vector<T>& out, const std::string& path) {
  try {
    const char* p = find_blob(file, data_start, table, name, count * sizeof(T));
    out.resize(count);
    if (count) std::memcpy(out.data(), p, count * sizeof(T));
  } catch (const BlobTableError& e) {
    corrupt(path, e.what());
  }
}

FieldState parse_field(const json& h, const json& table, std::string_view file, size_t start,
                       const std::string& prefix, const std::string& path) {
  FieldState f;
  const uint64_t n = h.at("params").get<uint64_t>();
  const uint32_t res = h.at("occupancy_res").get<uint32_t>();
  if (n == 0 || n > (uint64_t(1) << 32)) corrupt(path, fmt::format("'{}.params' is {}", prefix, n));
  if (res < 1 || res > 1024) corrupt(path, fmt::format("'{}.occupancy_res' is {}", prefix, res));
  f.adam.t = h.at("adam_t").get<uint64_t>();
  f.occupancy.res = res;
  f.occupancy_updates = h.at("occupancy_updates").get<uint32_t>();
  const size_t cells = size_t(res) * res * res;
  read_blob(table, file, start, prefix + ".params", n, f.params, path);
  read_blob(table, file, start, prefix + ".adam_m", n, f.adam.m, path);
  read_blob(table, file, start, prefix + ".adam_v", n, f.adam.v, path);
  read_blob(table, file, start, prefix + ".occupancy_bits", occ_word_count(res), f.occupancy.bits, path);
  read_blob(table, file, start, prefix + ".occupancy_density", h.at("has_density").get<bool>() ? cells : 0,
            f.occupancy.density, path);
  for (const auto* v : {&f.params, &f.adam.m, &f.adam.v, &f.occupancy.density})
    for (float x : *v)
      if (!std::isfinite(x)) corrupt(path, "non-finite values in '" + prefix + "'");
  return f;
}

TrainingState parse_state(const json& h, std::string_view file, size_t start, const std::string& path) {
  TrainingState s;
  s.step = h.at("step").get<uint64_t>();
  s.samples = h.at("samples").get<uint64_t>();
  s.rays = h.at("rays").get<uint64_t>();
  s.n_rays = h.at("n_rays").get<uint32_t>();
  s.elapsed = h.at("elapsed").get<double>();
  s.last_loss = h.at("last_loss").get<double>();
  s.room_samples = h.at("room_samples").get<uint64_t>();
  const json& table = h.at("blobs");
  s.subject = parse_field(h.at("subject"), table, file, start, "subject", path);
  if (!h.at("room").is_null()) s.room = parse_field(h.at("room"), table, file, start, "room", path);
  if (!std::isfinite(s.elapsed) || s.elapsed < 0.0) corrupt(path, "'elapsed' must be a finite time");
  return s;
}

}  // namespace

std::string checkpoint_path_for(const std::string& model_path) { return model_path + ".ckpt"; }

std::string encode_checkpoint(const CheckpointKey& key, const TrainingState& s) {
  std::vector<BlobRef> blobs;
  add_field_blobs("subject", s.subject, blobs);
  if (s.room) add_field_blobs("room", *s.room, blobs);
  json h = {{"format", "lorgnette-training-checkpoint"},
            {"version", kCheckpointVersion},
            {"dataset_hash", key.dataset_hash},
            {"settings", key.settings},
            {"step", s.step},
            {"samples", s.samples},
            {"rays", s.rays},
            {"n_rays", s.n_rays},
            {"elapsed", s.elapsed},
            {"last_loss", std::isfinite(s.last_loss) ? s.last_loss : 0.0},
            {"room_samples", s.room_samples},
            {"subject", field_header(s.subject)},
            {"room", s.room ? field_header(*s.room) : json(nullptr)},
            {"blobs", blob_table(blobs)}};
  const std::string text = h.dump();
  const uint64_t hlen = text.size(), hsum = snapshot_checksum(text);
  std::string out(kMagic, 8);
  out.append(reinterpret_cast<const char*>(&hlen), 8);
  out.append(reinterpret_cast<const char*>(&hsum), 8);
  out += text;
  append_blobs(out, blobs);
  return out;
}

TrainingState parse_checkpoint(std::string_view file, const std::string& path, CheckpointKey& key) {
  if (file.size() < kPrefix || std::memcmp(file.data(), kMagic, 8) != 0)
    corrupt(path, file.size() < kPrefix ? "the file is truncated" : "bad magic bytes");
  uint64_t hlen = 0, hsum = 0;
  std::memcpy(&hlen, file.data() + 8, 8);
  std::memcpy(&hsum, file.data() + 16, 8);
  if (hlen > file.size() - kPrefix) corrupt(path, "the file is truncated: the header ends past its end");
  const std::string_view text = file.substr(kPrefix, hlen);
  if (snapshot_checksum(text) != hsum) corrupt(path, "checksum mismatch in the header");
  try {
    const json h = json::parse(text);
    if (h.at("format") != "lorgnette-training-checkpoint") corrupt(path, "not a training checkpoint");
    const uint32_t version = h.at("version").get<uint32_t>();
    if (version != kCheckpointVersion)
      corrupt(path, fmt::format("version {}; this Lorgnette reads version {}", version, kCheckpointVersion));
    key.dataset_hash = h.at("dataset_hash").get<std::string>();
    key.settings = h.at("settings").get<std::string>();
    return parse_state(h, file, kPrefix + hlen, path);
  } catch (const json::exception& e) {
    corrupt(path, std::string("bad header: ") + e.what());
  }
}

void check_checkpoint_key(const CheckpointKey& want, const CheckpointKey& found, const std::string& path) {
  if (found.dataset_hash != want.dataset_hash)
    throw CheckpointMismatch(fmt::format(
        "training checkpoint '{}' belongs to another dataset (fingerprint {}, this one {}): it cannot "
        "continue this training; remove it or train without resuming",
        path, found.dataset_hash, want.dataset_hash));
  if (found.settings == want.settings) return;
  std::string what = "the settings";
  const json a = json::parse(found.settings, nullptr, false), b = json::parse(want.settings, nullptr, false);
  if (a.is_object() && b.is_object())
    for (const auto& [name, value] : b.items())
      if (!a.contains(name) || a.at(name) != value) {
        what = fmt::format("'{}' ({} there, {} now)", name, a.contains(name) ? a.at(name).dump() : "absent",
                           value.dump());
        break;
      }
  throw CheckpointMismatch(fmt::format(
      "training checkpoint '{}' was written by a training with other settings: {} differs. Resume with "
      "the settings it was started with, or remove it to train from the start",
      path, what));
}

void write_checkpoint(const std::string& path, const CheckpointKey& key, const TrainingState& state) {
  write_file_atomic(path, encode_checkpoint(key, state));
}

std::optional<TrainingState> read_checkpoint(const std::string& path, const CheckpointKey& key) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return std::nullopt;
  if (!std::filesystem::is_regular_file(path, ec))
    throw CheckpointCorrupt("training checkpoint '" + path +
                            "' is not a file: remove it to train from the start");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw CheckpointCorrupt("cannot open the training checkpoint '" + path + "': check its permissions");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CheckpointKey found;
  TrainingState s = parse_checkpoint(bytes, path, found);
  check_checkpoint_key(key, found, path);
  return s;
}

}  // namespace lorgnette::nerf
