// placement.json round trip, and refusal of newer versions and malformed files with named fields.
#include "fit/placement_json.h"

#include <fstream>

#include <gtest/gtest.h>

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
