// NerfModel snapshots: a save/load round trip restores everything bitwise; truncated, corrupted,
// foreign and newer files are refused with a clear message; an existing file is replaced atomically.
// The format alone (no device): NaN losses round-trip, out-of-range header numbers are refused.
#include "host/nerf/model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "kernels/train/occupancy.h"

namespace {

using namespace lorgnette;
using nerf::NerfModel;

field::FieldConfig tiny_config() {
  field::FieldConfig c;
  c.log2_table_size = 10;
  c.finest_resolution = 32;
  return c;
}

std::string tmp(const std::string& name) { return std::string(LORGNETTE_TEST_TMP) + "/nerf_" + name; }

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
void spit(const std::string& path, const std::string& data) { std::ofstream(path, std::ios::binary) << data; }

NerfModel make_model(cl::Runtime& rt) {
  nerf::Aabb box{{-1.0f, -0.5f, -2.0f}, {1.0f, 0.75f, 0.5f}};
  NerfModel m(rt, tiny_config(), box, 16, 0.01f, 256, 42, true);
  nerf::OccupancyGrid g = nerf::full_occupancy(16);
  g.density.assign(16 * 16 * 16, 0.0f);
  for (size_t i = 0; i < g.density.size(); ++i) g.density[i] = float(i % 17);
  for (size_t w = 0; w < g.bits.size(); ++w) g.bits[w] = 0x9e3779b9u * uint32_t(w + 1);
  m.set_occupancy(g);
  m.metadata.steps = 123;
  m.metadata.train_seconds = 4.5;
  m.metadata.dataset_path = "/some/data";
  m.normalisation.scale = 2.0f;
  return m;
}

std::string expect_load_error(cl::Runtime& rt, const std::string& path) {
  try {
    NerfModel::load(rt, path, 256);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  ADD_FAILURE() << "loading " << path << " should fail";
  return "";
}

TEST(NerfModel, SnapshotRoundTripIsBitwise) {
  cl::Runtime rt({"", "", false});
  NerfModel m = make_model(rt);
  std::string path = tmp("roundtrip.lnerf");
  m.save(path);
  NerfModel back = NerfModel::load(rt, path, 256);
  EXPECT_TRUE(back.field_config() == m.field_config());
  EXPECT_EQ(back.field().download_params(), m.field().download_params());
  EXPECT_EQ(back.aabb().min, m.aabb().min);
  EXPECT_EQ(back.aabb().max, m.aabb().max);
  EXPECT_EQ(back.step(), m.step());
  EXPECT_EQ(back.occupancy().res, 16u);
  EXPECT_EQ(back.occupancy().bits, m.occupancy().bits);
  EXPECT_EQ(back.occupancy().density, m.occupancy().density);
  EXPECT_EQ(back.occupancy_bits().read(rt), m.occupancy().bits);
  EXPECT_EQ(back.metadata.steps, 123u);
  EXPECT_EQ(back.metadata.dataset_path, "/some/data");
  EXPECT_EQ(back.normalisation.scale, 2.0f);
  // Saving again over the same path replaces it (atomic rename) and leaves no temporary file.
  back.save(path);
  for (auto& e : std::filesystem::directory_iterator(LORGNETTE_TEST_TMP))
    EXPECT_EQ(e.path().string().find("roundtrip.lnerf."), std::string::npos) << e.path();
}

TEST(NerfModel, CorruptTruncatedAndForeignFilesAreRefused) {
  cl::Runtime rt({"", "", false});
  std::string good = tmp("good.lnerf");
  make_model(rt).save(good);
  std::string data = slurp(good);

  std::string flipped = data;
  flipped[flipped.size() - 100] ^= 0x5a;  // inside the last blob
  spit(tmp("flipped.lnerf"), flipped);
  EXPECT_NE(expect_load_error(rt, tmp("flipped.lnerf")).find("checksum"), std::string::npos);

  spit(tmp("truncated.lnerf"), data.substr(0, data.size() - 10));
  EXPECT_NE(expect_load_error(rt, tmp("truncated.lnerf")).find("truncated"), std::string::npos);

  spit(tmp("foreign.lnerf"), "PNG\x0d\x0a this is not a model at all, just some bytes");
  EXPECT_NE(expect_load_error(rt, tmp("foreign.lnerf")).find("not a Lorgnette model"), std::string::npos);

  std::string bad_header = data;
  bad_header[20] = '#';  // breaks the JSON
  spit(tmp("badheader.lnerf"), bad_header);
  EXPECT_NE(expect_load_error(rt, tmp("badheader.lnerf")).find("corrupt"), std::string::npos);

  EXPECT_NE(expect_load_error(rt, tmp("does-not-exist.lnerf")).find("cannot open"), std::string::npos);
}

TEST(NerfModel, NewerFormatVersionIsRefused) {
  cl::Runtime rt({"", "", false});
  std::string path = tmp("newer.lnerf");
  make_model(rt).save(path);
  std::string data = slurp(path);
  uint64_t hlen = 0;
  std::memcpy(&hlen, data.data() + 8, 8);
  nlohmann::json header = nlohmann::json::parse(data.substr(16, hlen));
  header["version"] = nerf::kSnapshotVersion + 1;
  std::string text = header.dump();
  uint64_t new_len = text.size();
  std::string out = data.substr(0, 8) + std::string(reinterpret_cast<const char*>(&new_len), 8) + text +
                    data.substr(16 + hlen);
  spit(path, out);
  std::string msg = expect_load_error(rt, path);
  EXPECT_NE(msg.find("newer"), std::string::npos) << msg;
  EXPECT_NE(msg.find("update"), std::string::npos) << msg;
}

// The format alone, no device (host/nerf/snapshot.h).
nerf::Snapshot host_snapshot() {
  nerf::Snapshot s;
  s.config = tiny_config();
  s.aabb = {{-1.0f, -0.5f, -2.0f}, {1.0f, 0.75f, 0.5f}};
  s.step = 0.01f;
  s.params.assign(s.config.param_count(), 0.25f);
  s.occ = nerf::full_occupancy(4);
  s.metadata.seed = 9;
  return s;
}

// A snapshot with its header replaced by `edit(header)`, sealed with the edited header's checksum
// (so only the edit, not the checksum, decides whether it reads).
std::string with_header(const std::string& file, const std::function<void(nlohmann::json&)>& edit) {
  uint64_t hlen = 0;
  std::memcpy(&hlen, file.data() + 8, 8);
  nlohmann::json header = nlohmann::json::parse(file.substr(16, hlen));
  edit(header);
  std::string text = nerf::seal_header(header.dump());
  uint64_t new_len = text.size();
  return file.substr(0, 8) + std::string(reinterpret_cast<const char*>(&new_len), 8) + text +
         file.substr(16 + hlen);
}

TEST(Snapshot, DivergedLossIsWrittenAsNullAndReadsBackAsNan) {
  nerf::Snapshot s = host_snapshot();
  s.metadata.final_loss = NAN;
  nerf::Snapshot back = nerf::parse_snapshot(nerf::encode_snapshot(s), "nan.lnerf");
  EXPECT_TRUE(std::isnan(back.metadata.final_loss));
  EXPECT_EQ(back.metadata.seed, 9u);
  EXPECT_EQ(back.params, s.params);
}

// The hole check's figures (subject_holes.h) round-trip; a file without them reads as not checked,
// and a share outside [-1, 1] is refused naming the field.
TEST(Snapshot, HoleFiguresRoundTripAndDefaultToUnchecked) {
  nerf::Snapshot s = host_snapshot();
  EXPECT_EQ(s.metadata.holes, -1.0);
  s.metadata.holes = 0.0375, s.metadata.holes_worst_view = 0.125;
  const std::string file = nerf::encode_snapshot(s);
  nerf::Snapshot back = nerf::parse_snapshot(file, "holes.lnerf");
  EXPECT_EQ(back.metadata.holes, 0.0375);
  EXPECT_EQ(back.metadata.holes_worst_view, 0.125);
  auto erase = [](nlohmann::json& h) {
    h["metadata"].erase("holes"), h["metadata"].erase("holes_worst_view");
  };
  EXPECT_EQ(nerf::parse_snapshot(with_header(file, erase), "old.lnerf").metadata.holes, -1.0);
  try {
    nerf::parse_snapshot(with_header(file, [](nlohmann::json& h) { h["metadata"]["holes"] = 7.0; }),
                         "bad.lnerf");
    ADD_FAILURE() << "a hole share of 7 was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("metadata.holes"), std::string::npos) << e.what();
  }
}

// Found by fuzzing (fuzz/regressions/snapshot/): header numbers beyond their type were cast anyway
// (undefined behaviour); each is refused naming the field.
TEST(Snapshot, HeaderNumbersBeyondTheirTypeAreRefused) {
  const std::string good = nerf::encode_snapshot(host_snapshot());
  const std::pair<const char*, std::function<void(nlohmann::json&)>> cases[] = {
      {"version", [](nlohmann::json& h) { h["version"] = 1e300; }},
      {"occupancy.res", [](nlohmann::json& h) { h["occupancy"]["res"] = -1e20; }},
      {"step", [](nlohmann::json& h) { h["step"] = 1e300; }},
      {"aabb.max", [](nlohmann::json& h) { h["aabb"]["max"][0] = 1e39; }},
      {"blobs.offset", [](nlohmann::json& h) { h["blobs"][0]["offset"] = 1e300; }},
      {"metadata.steps", [](nlohmann::json& h) { h["metadata"]["steps"] = -1.5e19; }},
  };
  for (const auto& [field, edit] : cases) {
    try {
      nerf::parse_snapshot(with_header(good, edit), "bad.lnerf");
      ADD_FAILURE() << field << " was accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("corrupt"), std::string::npos) << e.what();
    }
  }
}

TEST(Occupancy, IndexAndCellExitFollowTheSharedRule) {
  EXPECT_EQ(occ_cell_index(4, 0.0f, 0.0f, 0.0f), 0);
  EXPECT_EQ(occ_cell_index(4, 0.3f, 0.55f, 0.99f), 1 + 4 * (2 + 4 * 3));
  EXPECT_EQ(occ_cell_index(4, 1.0f, 0.5f, 0.5f), -1);
  EXPECT_EQ(occ_cell_index(4, -0.01f, 0.5f, 0.5f), -1);
  EXPECT_EQ(occ_cell_index(4, NAN, 0.5f, 0.5f), -1);
  // From x = 0.3 in a 4-cell grid moving +x at 0.5 per unit: the cell ends at 0.5 -> 0.4 units.
  EXPECT_NEAR(occ_cell_exit(4, 0.3f, 0.1f, 0.1f, 0.5f, 0.0f, 0.0f), 0.4f, 1e-6f);
  EXPECT_NEAR(occ_cell_exit(4, 0.3f, 0.1f, 0.1f, -1.0f, 0.0f, 0.0f), 0.05f, 1e-6f);
  std::vector<uint32_t> bits(occ_word_count(4), 0u);
  bits[37 >> 5] |= 1u << (37 & 31);
  EXPECT_TRUE(occ_cell_occupied(bits.data(), 37));
  EXPECT_FALSE(occ_cell_occupied(bits.data(), 36));
  EXPECT_FALSE(occ_cell_occupied(bits.data(), -1));
}

}  // namespace
