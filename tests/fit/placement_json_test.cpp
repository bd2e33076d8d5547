// placement.json round trip (with and without the temple spread and the hand nudge), hand-written
// files, refusal of newer versions, malformed files and broken transforms with named fields, glasses
// paths relative to the file whatever the working directory, and the check that a placement belongs
// to the glasses file it is used with.
#include "fit/placement_json.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>

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
  // The same file, named from the working directory as before.
  auto full = [](const std::string& g) {
    return std::filesystem::weakly_canonical(std::filesystem::absolute(g));
  };
  EXPECT_EQ(full(q.glasses_path), full(p.glasses_path));
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
  EXPECT_EQ(std::filesystem::path(p.glasses_path), std::filesystem::path(dir) / "frame.glb");
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

// `fit` runs in one directory and `render --placement` in another: the path is stored relative to
// the placement's folder and resolved against it, so the reader finds the frame from anywhere.
TEST(PlacementJson, RelativeGlassesPathIsRelativeToThePlacementsFolder) {
  namespace fs = std::filesystem;
  const fs::path root = fs::path(LORGNETTE_TEST_TMP) / "placement_cwd";
  fs::remove_all(root);
  fs::create_directories(root / "work" / "frames");
  fs::create_directories(root / "work" / "out");
  fs::create_directories(root / "elsewhere");
  std::ofstream(root / "work" / "frames" / "g.glb") << "frame";
  const fs::path before = fs::current_path();
  ASSERT_EQ(::chdir((root / "work").c_str()), 0);
  PlacementFile p;
  p.glasses_path = "frames/g.glb";  // as the user typed it in `work`
  p.glasses_hash = file_hash(p.glasses_path);
  write_placement("out/placement.json", p);
  std::ifstream in("out/placement.json");
  EXPECT_EQ(nlohmann::json::parse(in)["glasses"]["path"], "../frames/g.glb");
  ASSERT_EQ(::chdir((root / "elsewhere").c_str()), 0);
  PlacementFile q = read_placement("../work/out/placement.json");
  EXPECT_TRUE(fs::exists(q.glasses_path)) << q.glasses_path;
  EXPECT_TRUE(fs::equivalent(q.glasses_path, root / "work" / "frames" / "g.glb"));
  EXPECT_EQ(glasses_mismatch(q, q.glasses_path), "");
  // Absolute paths stay absolute.
  p.glasses_path = (root / "work" / "frames" / "g.glb").string();
  write_placement("abs.json", p);
  EXPECT_EQ(read_placement("abs.json").glasses_path, p.glasses_path);
  ASSERT_EQ(::chdir(before.c_str()), 0);
}

// Transforms that place nothing visible or nothing at all are refused by the reader (so by render,
// the viewer and Python alike) and by the writer, with the field named.
TEST(PlacementJson, RefusesBrokenTransforms) {
  auto with = [](const std::function<void(Transform&)>& edit) {
    PlacementFile p;
    p.transform = Transform::Identity() * 0.01;
    p.transform(3, 3) = 1.0;
    edit(p.transform);
    return p;
  };
  const std::pair<const char*, std::function<void(Transform&)>> cases[] = {
      {"all zero", [](Transform& m) { m.setZero(); }},
      {"all zero but the last row", [](Transform& m) { m.block<3, 4>(0, 0).setZero(); }},
      {"1e300 scale", [](Transform& m) { m.block<3, 3>(0, 0) *= 1e302; }},
      {"NaN", [](Transform& m) { m(1, 2) = NAN; }},
      {"infinite translation", [](Transform& m) { m(0, 3) = INFINITY; }},
      {"non-affine last row", [](Transform& m) { m(3, 2) = 1.0; }},
      {"flat", [](Transform& m) { m.col(2) = m.col(0); }},
  };
  const std::string path = std::string(LORGNETTE_TEST_TMP) + "/placement_broken.json";
  for (const auto& [name, edit] : cases) {
    PlacementFile p = with(edit);
    std::filesystem::remove(path);
    EXPECT_THROW(write_placement(path, p), std::runtime_error) << name;
    EXPECT_FALSE(std::filesystem::exists(path)) << name;
    // The same matrix written by hand (JSON writes NaN and infinity as null).
    nlohmann::json j = to_json(PlacementFile{});
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) j["transform"][r][c] = p.transform(r, c);
    std::ofstream(path) << j.dump();
    try {
      read_placement(path);
      ADD_FAILURE() << name << " was read";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("transform"), std::string::npos) << name << ": " << e.what();
    }
  }
  EXPECT_NO_THROW(write_placement(path, with([](Transform&) {})));
}

TEST(PlacementJson, AGlassesFileOtherThanTheFittedOneIsNamed) {
  const std::string dir = std::string(LORGNETTE_TEST_TMP) + "/placement_hash";
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/a.glb") << "frame a";
  std::ofstream(dir + "/b.glb") << "frame b";
  PlacementFile p;
  p.glasses_path = dir + "/a.glb";
  p.glasses_hash = file_hash(p.glasses_path);
  EXPECT_EQ(glasses_mismatch(p, dir + "/a.glb"), "");
  std::string why = glasses_mismatch(p, dir + "/b.glb");
  EXPECT_NE(why.find("another glasses file"), std::string::npos) << why;
  EXPECT_NE(why.find("b.glb"), std::string::npos) << why;
  p.glasses_hash.clear();  // hand-written: nothing to compare
  EXPECT_EQ(glasses_mismatch(p, dir + "/b.glb"), "");
}

// The viewer's hand nudge is a field of the format; files written with the earlier "viewer" object
// still read it.
TEST(PlacementJson, NudgeRoundTripAndTheEarlierViewerObject) {
  PlacementFile p;
  p.has_nudge = true;
  p.nudge = {1.5, -0.5, 3.0};
  p.transform = p.transform * nudge_matrix(p.nudge);
  const std::string path = std::string(LORGNETTE_TEST_TMP) + "/placement_nudge.json";
  write_placement(path, p);
  PlacementFile q = read_placement(path);
  ASSERT_TRUE(q.has_nudge);
  EXPECT_EQ(q.nudge.up_mm, 1.5);
  EXPECT_EQ(q.nudge.forward_mm, -0.5);
  EXPECT_EQ(q.nudge.tilt_deg, 3.0);
  // nudge_matrix: 1.5 mm up, -0.5 mm forward, tilted about x.
  EXPECT_NEAR(q.transform(1, 3), 1.5, 1e-12);
  EXPECT_NEAR(q.transform(2, 3), -0.5, 1e-12);
  EXPECT_NEAR(q.transform(1, 2), -std::sin(3.0 * M_PI / 180.0), 1e-12);
  nlohmann::json legacy = to_json(PlacementFile{});
  legacy["viewer"] = {{"nudge", {{"up_mm", 2.0}, {"forward_mm", 0.0}, {"tilt_deg", 0.0}}}, {"note", "x"}};
  PlacementFile r = placement_from_json(legacy);
  EXPECT_TRUE(r.has_nudge);
  EXPECT_EQ(r.nudge.up_mm, 2.0);
  EXPECT_FALSE(placement_from_json(to_json(PlacementFile{})).has_nudge);
  // Two saves' nudges recorded as one.
  PlacementNudge a{1.0, 2.0, 10.0}, b{-3.0, 0.5, -4.0};
  EXPECT_NEAR((nudge_matrix(combined_nudge(a, b)) - nudge_matrix(a) * nudge_matrix(b)).norm(), 0.0, 1e-12);
}

}  // namespace
}  // namespace lorgnette::fit
