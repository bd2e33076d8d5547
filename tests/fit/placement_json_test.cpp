// placement.json round trip (with and without the temple spread), hand-written files, and refusal of
// newer versions and malformed files with named fields.
#include "fit/placement_json.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace lorgnette::fit {
namespace {

TEST(PlacementJson, RoundTrip) {
  PlacementFile p;
  p.glasses_path = "frame.glb";
  p.glasses_hash = "fnv1a64:0123456789abcdef";
  p.transform(0, 3) = 0.25;
  p.transform(1, 1) = 0.018;
  p.scale_policy = "true-size";
  p.scale = 0.018;
  p.mm_per_unit = 55.5;
  p.pd_mm = 63.1;
  p.landmarks["nose"] = {Eigen::Vector3d(0.1, 0.2, 0.3), 0.4, 11};
  p.residuals_px["nose"] = 1.25;
  p.views_used = 11;
  p.views_total = 12;
  p.penetration_mm = 0.125;
  p.seconds = {{"front", 0.5}, {"triangulate", 0.01}};
  p.ok = true;
  const std::string path = std::string(LORGNETTE_TEST_TMP) + "/placement_roundtrip.json";
  write_placement(path, p);
  PlacementFile q = read_placement(path);
  EXPECT_EQ(q.glasses_path, p.glasses_path);
  EXPECT_EQ(q.glasses_hash, p.glasses_hash);
  EXPECT_EQ(q.transform, p.transform);  // JSON doubles round-trip exactly
  EXPECT_EQ(q.scale_policy, "true-size");
  EXPECT_EQ(q.mm_per_unit, 55.5);
  EXPECT_EQ(q.landmarks.at("nose").position, p.landmarks.at("nose").position);
  EXPECT_EQ(q.landmarks.at("nose").views, 11);
  EXPECT_EQ(q.residuals_px.at("nose"), 1.25);
  EXPECT_EQ(q.seconds, p.seconds);
  EXPECT_TRUE(q.ok);
}

TEST(PlacementJson, TemplesRoundTrip) {
  PlacementFile p;
  p.has_temples = true;
  p.temples.fitted = true;
  p.temples.bend.left.hinge = {66.5, 11.25, -3.5};
  p.temples.bend.right.hinge = {-66.5, 11.25, -3.5};
  p.temples.bend.left.spread_deg = p.temples.left.spread_deg = 4.75;
  p.temples.bend.right.spread_deg = p.temples.right.spread_deg = 0.0;
  p.temples.bend.ramp_mm = 3.0;
  p.temples.left = {4.75, 11.5, 0.25, 420, true};
  p.temples.right = {0.0, 0.0, 0.0, 410, true};
  const std::string path = std::string(LORGNETTE_TEST_TMP) + "/placement_temples.json";
  write_placement(path, p);
  PlacementFile q = read_placement(path);
  ASSERT_TRUE(q.has_temples);
  EXPECT_EQ(q.temples.bend.left.hinge, p.temples.bend.left.hinge);
  EXPECT_EQ(q.temples.bend.right.hinge, p.temples.bend.right.hinge);
  EXPECT_EQ(q.temples.bend.left.spread_deg, 4.75);
  EXPECT_EQ(q.temples.bend.ramp_mm, 3.0);
  EXPECT_EQ(q.temples.left.spread_deg, 4.75);
  EXPECT_EQ(q.temples.left.penetration_before_mm, 11.5);
  EXPECT_EQ(q.temples.left.penetration_mm, 0.25);
  EXPECT_EQ(q.temples.right.points, 410);
  mesh::TempleBend b = read_placement(path).temples.bend;  // what `lorgnette render` applies
  EXPECT_EQ(b.left.hinge, p.temples.bend.left.hinge);
  EXPECT_EQ(b.left.spread_deg, 4.75);
  EXPECT_EQ(b.right.spread_deg, 0.0);
  EXPECT_EQ(b.ramp_mm, 3.0);
  // Without temples (as every file written before them): no "temples" key, read back as rigid.
  PlacementFile rigid;
  EXPECT_FALSE(to_json(rigid).contains("temples"));
  write_placement(path, rigid);
  q = read_placement(path);
  EXPECT_FALSE(q.has_temples);
  EXPECT_FALSE(q.temples.bend.active());
  EXPECT_FALSE(read_placement(path).temples.bend.active());
  nlohmann::json bad = to_json(p);
  bad["temples"]["spread_l_deg"] = "wide";
  EXPECT_THROW(placement_from_json(bad), std::runtime_error);
}

// The "temples" object alone (moved here with the codec from tests/mesh/temple_bend_test.cpp).
TEST(PlacementJson, TemplesCodec) {
  mesh::TempleBend b;
  b.left.hinge = {66.0, 12.0, -4.0};
  b.right.hinge = {-66.0, 12.0, -4.0};
  b.left.spread_deg = 3.25;
  b.right.spread_deg = 11.5;
  nlohmann::json placement = {{"version", 1}, {"temples", temple_bend_to_json(b)}};
  mesh::TempleBend c = temple_bend_from_placement(placement);
  EXPECT_EQ(c.left.hinge, b.left.hinge);
  EXPECT_EQ(c.right.hinge, b.right.hinge);
  EXPECT_EQ(c.left.spread_deg, 3.25);
  EXPECT_EQ(c.right.spread_deg, 11.5);
  EXPECT_EQ(c.ramp_mm, b.ramp_mm);
  EXPECT_FALSE(temple_bend_from_placement({{"version", 1}}).active());  // an older file: rigid
  placement["temples"]["hinge_l"] = {1, 2};
  EXPECT_THROW(temple_bend_from_placement(placement), std::runtime_error);
  const std::string path = std::string(LORGNETTE_TEST_TMP) + "/temple_codec.json";
  std::ofstream(path) << nlohmann::json{
      {"version", 1},
      {"transform", {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}},
      {"temples", temple_bend_to_json(
                      b)}}.dump();
  EXPECT_EQ(read_placement(path).temples.bend.right.spread_deg, 11.5);
  EXPECT_THROW(read_placement("/nonexistent/p.json"), std::runtime_error);
}

// A hand-written placement (what `lorgnette render --placement` always accepted: a transform and a
// relative glasses path) reads through the same module; the glasses path is relative to the file
// (moved here from tests/host/render/render_job_test.cpp).
TEST(PlacementJson, HandWrittenFileAndRelativeGlassesPath) {
  const std::string dir = std::string(LORGNETTE_TEST_TMP) + "/placement_hand";
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/placement.json")
      << R"({"version":1,"glasses":{"path":"frame.glb"},"transform":[[0.01,0,0,0.1],[0,0.01,0,0.2],[0,0,0.01,0.3],[0,0,0,1]]})";
  PlacementFile p = read_placement(dir + "/placement.json");
  EXPECT_FLOAT_EQ(p.transform(0, 0), 0.01f);
  EXPECT_FLOAT_EQ(p.transform(2, 3), 0.3f);
  EXPECT_EQ(std::filesystem::path(glasses_file(p, dir + "/placement.json")),
            std::filesystem::path(dir) / "frame.glb");
  EXPECT_TRUE(p.ok);  // a transform given by hand is taken as given
  std::ofstream(dir + "/bad.json") << R"({"version":1})";
  EXPECT_THROW(read_placement(dir + "/bad.json"), std::runtime_error);
  EXPECT_THROW(read_placement(dir + "/missing.json"), std::runtime_error);
}

TEST(PlacementJson, RefusesNewerAndMalformed) {
  nlohmann::json j = to_json(PlacementFile{});
  j["version"] = PlacementFile::kVersion + 1;
  EXPECT_THROW(placement_from_json(j), std::runtime_error);
  j = to_json(PlacementFile{});
  j.erase("transform");
  try {
    placement_from_json(j);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("transform"), std::string::npos);
  }
  EXPECT_THROW(read_placement("/nonexistent/placement.json"), std::runtime_error);
}

// Found by fuzzing (fuzz/regressions/placement/): counts that do not fit an int were cast anyway
// (undefined behaviour); whole numbers written as 2.0 still read.
TEST(PlacementJson, CountsMustBeWholeNumbersThatFitAnInt) {
  nlohmann::json j = to_json(PlacementFile{});
  j["views_used"] = 2.0;
  EXPECT_EQ(placement_from_json(j).views_used, 2);
  for (const char* key : {"version", "views_used", "views_total"})
    for (double bad : {1e300, -3e9, 2.5}) {
      nlohmann::json k = to_json(PlacementFile{});
      k[key] = bad;
      try {
        placement_from_json(k);
        ADD_FAILURE() << key << " = " << bad << " was accepted";
      } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("whole number"), std::string::npos) << e.what();
      }
    }
}

TEST(PlacementJson, FileHashIsStable) {
  const std::string path = std::string(LORGNETTE_TEST_TMP) + "/hash_me.txt";
  {
    std::ofstream out(path, std::ios::binary);
    out << "a";
  }
  EXPECT_EQ(file_hash(path), "fnv1a64:af63dc4c8601ec8c");  // FNV-1a 64 of "a" (published test vector)
}

}  // namespace
}  // namespace lorgnette::fit
