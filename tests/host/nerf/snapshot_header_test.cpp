// The .lnerf header's own checksum (format version 2) and the ranges of its numbers
// (host/nerf/snapshot.h, host/util/bounds.h), on the format alone with no device: a flipped bit in
// the box, the step or the normalisation is refused with a clear message, a step that would march
// for hours is refused, version 1 files (no header checksum) still load, and a FIFO in the model's
// place is refused instead of blocking the reader.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstring>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "host/nerf/snapshot.h"

namespace lorgnette::nerf {
namespace {

Snapshot small_snapshot() {
  Snapshot s;
  s.config.log2_table_size = 10;
  s.config.finest_resolution = 32;
  s.aabb = {{-1.0f, -0.5f, -2.0f}, {1.0f, 0.75f, 0.5f}};
  s.step = 0.0123f;
  s.params.assign(s.config.param_count(), 0.25f);
  s.occ = full_occupancy(4);
  s.normalisation.scale = 0.5f;
  s.normalisation.offset = {0.25f, -0.125f, 1.0f};
  s.metadata.seed = 9;
  return s;
}

struct Parts {
  std::string header, blobs;
};
Parts split(const std::string& file) {
  uint64_t hlen = 0;
  std::memcpy(&hlen, file.data() + 8, 8);
  return {file.substr(16, hlen), file.substr(16 + hlen)};
}
std::string join(const std::string& header, const std::string& blobs) {
  uint64_t n = header.size();
  return std::string("LGNNERF\n") + std::string(reinterpret_cast<const char*>(&n), 8) + header + blobs;
}

// The file with its header edited as JSON, then sealed again (a consistent file with other values).
std::string resealed(const std::string& file, const std::function<void(nlohmann::json&)>& edit) {
  Parts p = split(file);
  nlohmann::json h = nlohmann::json::parse(p.header);
  edit(h);
  return join(seal_header(h.dump()), p.blobs);
}

// The file as a version 1 writer made it: the same header without its checksum.
std::string version1(const std::string& file) {
  Parts p = split(file);
  nlohmann::json h = nlohmann::json::parse(p.header);
  h["version"] = 1;
  h.erase(kHeaderChecksumKey);
  return join(h.dump(), p.blobs);
}

std::string load_error(const std::string& bytes) {
  try {
    parse_snapshot(bytes, "m.lnerf");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

#define EXPECT_HAS(text, part) EXPECT_NE((text).find(part), std::string::npos) << (text)

TEST(SnapshotHeader, IsSealedAndRoundTrips) {
  const Snapshot s = small_snapshot();
  const std::string file = encode_snapshot(s);
  nlohmann::json h = nlohmann::json::parse(split(file).header);
  EXPECT_EQ(h["version"], kSnapshotVersion);
  EXPECT_EQ(kSnapshotVersion, 2u);
  ASSERT_TRUE(h.contains(kHeaderChecksumKey));
  EXPECT_EQ(h[kHeaderChecksumKey].get<std::string>().size(), 16u);
  Snapshot back = parse_snapshot(file, "m.lnerf");
  EXPECT_EQ(back.step, s.step);
  EXPECT_EQ(back.aabb.max, s.aabb.max);
  EXPECT_EQ(back.normalisation.scale, s.normalisation.scale);
  EXPECT_EQ(back.params, s.params);
}

TEST(SnapshotHeader, Version1FilesWithoutAChecksumStillLoad) {
  const Snapshot s = small_snapshot();
  Snapshot back = parse_snapshot(version1(encode_snapshot(s)), "old.lnerf");
  EXPECT_EQ(back.step, s.step);
  EXPECT_EQ(back.aabb.min, s.aabb.min);
  EXPECT_EQ(back.normalisation.offset, s.normalisation.offset);
  EXPECT_EQ(back.metadata.seed, 9u);
  EXPECT_EQ(back.params, s.params);
}

// One bit of one digit flipped in the header's text: the value still parses and lies in range, so
// only the checksum can tell.
TEST(SnapshotHeader, AFlippedBitInTheBoxStepOrScaleIsRefused) {
  const std::string file = encode_snapshot(small_snapshot());
  const Parts p = split(file);
  for (const std::string key : {"\"max\":[", "\"step\":", "\"scale\":"}) {
    std::string header = p.header;
    size_t at = header.find(key);
    ASSERT_NE(at, std::string::npos) << key;
    size_t digit = header.find_first_of("123456789", at + key.size());
    header[digit] ^= 0x02;  // '1' <-> '3', '5' <-> '7', ...: still a digit
    std::string msg = load_error(join(header, p.blobs));
    EXPECT_HAS(msg, "checksum mismatch in the header");
    EXPECT_HAS(msg, "m.lnerf");
    // The same edit in a version 1 file loads: nothing there can see it (why version 2 exists).
    std::string old = version1(file);
    Parts q = split(old);
    size_t at1 = q.header.find(key);
    size_t digit1 = q.header.find_first_of("123456789", at1 + key.size());
    q.header[digit1] ^= 0x02;
    EXPECT_EQ(load_error(join(q.header, q.blobs)), "") << key;
  }
  // A missing checksum in a version 2 header is refused too.
  std::string unsealed = resealed(file, [](nlohmann::json& h) { h.erase(kHeaderChecksumKey); });
  EXPECT_HAS(load_error(unsealed), "checksum");
}

TEST(SnapshotHeader, StepsThatWouldMarchForHoursAreRefused) {
  const std::string file = encode_snapshot(small_snapshot());  // diagonal 3.44
  for (double step : {1e-30, 1e-9, 1e-4}) {
    std::string msg = load_error(resealed(file, [&](nlohmann::json& h) { h["step"] = step; }));
    EXPECT_HAS(msg, "steps across the box's diagonal");
    EXPECT_HAS(msg, "corrupt");
  }
  EXPECT_HAS(load_error(resealed(file, [](nlohmann::json& h) { h["step"] = 5.0; })), "outside 8..16384");
  EXPECT_EQ(load_error(resealed(file, [](nlohmann::json& h) { h["step"] = 0.001; })), "");  // 3440 steps
}

TEST(SnapshotHeader, BoxAndNormalisationOutOfRangeAreRefused) {
  const std::string file = encode_snapshot(small_snapshot());
  EXPECT_HAS(load_error(resealed(file, [](nlohmann::json& h) { h["aabb"]["min"][0] = -1e30; })),
             "bounding box");
  EXPECT_HAS(load_error(resealed(file, [](nlohmann::json& h) { h["normalisation"]["scale"] = -1.0; })),
             "'normalisation.scale' must be within 1e-06..1e+06");
  EXPECT_HAS(load_error(resealed(file, [](nlohmann::json& h) { h["normalisation"]["scale"] = 0.0; })),
             "normalisation.scale");
  EXPECT_HAS(load_error(resealed(file, [](nlohmann::json& h) { h["normalisation"]["offset"][1] = 1e30; })),
             "normalisation.offset");
}

// The metric scale `train` carries from scale.json: written under metadata.metric_scale and read back
// exactly; absent (unknown) in models without one and in files written before it existed; a
// non-positive scale, a negative uncertainty or a missing source is refused with the key's name.
TEST(SnapshotHeader, MetricScaleRoundTripsAndAbsentMeansUnknown) {
  Snapshot s = small_snapshot();
  const std::string without = encode_snapshot(s);
  EXPECT_FALSE(nlohmann::json::parse(split(without).header)["metadata"].contains("metric_scale"));
  EXPECT_FALSE(parse_snapshot(without, "m.lnerf").metadata.metric_scale.has_value());
  EXPECT_FALSE(parse_snapshot(version1(without), "old.lnerf").metadata.metric_scale.has_value());
  s.metadata.metric_scale = MetricScale{"card", 412.75, 1.25};
  const std::string file = encode_snapshot(s);
  nlohmann::json m = nlohmann::json::parse(split(file).header)["metadata"]["metric_scale"];
  EXPECT_EQ(m["source"], "card");
  EXPECT_EQ(m["mm_per_unit"].get<double>(), 412.75);
  EXPECT_EQ(m["mm_per_unit_uncertainty"].get<double>(), 1.25);
  Snapshot back = parse_snapshot(file, "m.lnerf");
  ASSERT_TRUE(back.metadata.metric_scale.has_value());
  EXPECT_EQ(back.metadata.metric_scale->source, "card");
  EXPECT_EQ(back.metadata.metric_scale->mm_per_unit, 412.75);
  EXPECT_EQ(back.metadata.metric_scale->uncertainty, 1.25);
  auto edited = [&](const char* key, nlohmann::json v) {
    return load_error(resealed(file, [&](nlohmann::json& h) { h["metadata"]["metric_scale"][key] = v; }));
  };
  EXPECT_HAS(edited("mm_per_unit", -3.0), "metadata.metric_scale.mm_per_unit");
  EXPECT_HAS(edited("mm_per_unit", 0.0), "must be positive");
  EXPECT_HAS(edited("mm_per_unit_uncertainty", -0.5), "metadata.metric_scale.mm_per_unit_uncertainty");
  EXPECT_HAS(edited("source", ""), "metadata.metric_scale.source");
  EXPECT_HAS(load_error(resealed(file, [](nlohmann::json& h) { h["metadata"]["metric_scale"] = 5; })),
             "must be an object");
}

TEST(SnapshotHeader, AFifoInTheModelsPlaceIsRefusedNotOpened) {
  std::string path = std::string(LORGNETTE_TEST_TMP) + "/snapshot_fifo.lnerf";
  std::filesystem::remove(path);
  ASSERT_EQ(mkfifo(path.c_str(), 0600), 0);
  try {
    read_snapshot(path);  // opening a FIFO for reading would block here until a writer came
    ADD_FAILURE() << "a FIFO was read";
  } catch (const std::runtime_error& e) {
    EXPECT_HAS(std::string(e.what()), "FIFO");
    EXPECT_HAS(std::string(e.what()), "not a regular file");
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace lorgnette::nerf
