// The reference-point sidecar (<frame>.refpoints.json, mesh/refpoints.h) and the glasses' units
// override: coordinates beyond bounds::kMeshCoord (1e300 is infinite as a float) and an mm_per_unit
// that is negative, NaN or absurd are refused naming the file and the key, where they used to give
// -inf/NaN points (`glasses inspect` exited 0) or a frame that `render` silently dropped.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>

#include "host/util/bounds.h"
#include "mesh/glasses.h"
#include "mesh/gltf_writer.h"
#include "mesh/parametric.h"

namespace lorgnette::mesh {
namespace {

namespace fs = std::filesystem;

#define EXPECT_HAS(text, part) EXPECT_NE(std::string(text).find(part), std::string::npos) << (text)

// A 52-18-140 parametric frame as a .glb (metres) in a fresh folder of the running test's own (ctest
// runs the tests of this file in parallel processes), and its sidecar's true points.
struct FrameFile {
  std::string path;
  RefPointsSidecar sidecar;
  FrameFile() {
    fs::path dir = fs::path(LORGNETTE_TEST_TMP) / "refpoints_sidecar" /
                   ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir);
    fs::create_directories(dir);
    path = (dir / "frame.glb").string();
    ParametricFrame frame = make_parametric_frame(FrameParams{});
    write_glb(path, frame.mesh);
    sidecar.points = frame.ref;
    sidecar.points.g_l /= 1000.0f, sidecar.points.g_r /= 1000.0f;  // file units are metres
  }
  void write_sidecar(const std::string& text) const { std::ofstream(sidecar_path(path)) << text; }
};

std::string error_of(const std::string& path, GlassesOptions opts = {}) {
  try {
    load_glasses(path, opts);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(RefPointsSidecar, HugeOrNonFiniteCoordinatesAreRefusedNamingTheKey) {
  FrameFile f;
  write_refpoints_sidecar(f.path, f.sidecar);
  Glasses good = load_glasses(f.path);  // the writer's own sidecar loads
  EXPECT_EQ(good.ref.source, "sidecar");
  EXPECT_TRUE(good.ref.g_l.allFinite());
  f.write_sidecar(R"({"version": 1, "g_c": [0, 0, 0], "g_l": [1e300, 0, 0], "g_r": [-0.07, 0, -0.1]})");
  std::string msg = error_of(f.path);
  EXPECT_HAS(msg, "refpoints.json");
  EXPECT_HAS(msg, "'g_l' must hold coordinates within +-1e+07");
  f.write_sidecar(R"({"version": 1, "g_c": [0, 0, 0], "g_l": [NaN, 0, 0], "g_r": [-0.07, 0, -0.1]})");
  EXPECT_HAS(error_of(f.path), "not valid JSON");
}

TEST(RefPointsSidecar, MmPerUnitOutsideItsRangeIsRefusedNotTakenAsDetect) {
  FrameFile f;
  RefPointsSidecar s = f.sidecar;
  s.mm_per_unit = 1000.0;
  f.write_sidecar(refpoints_sidecar_text(s));
  EXPECT_DOUBLE_EQ(load_glasses(f.path).canonical.mm_per_unit, 1000.0);
  for (const char* bad : {"-1", "1e300", "1e-9"}) {
    nlohmann::json j = nlohmann::json::parse(refpoints_sidecar_text(s));
    j["mm_per_unit"] = nlohmann::json::parse(bad);
    f.write_sidecar(j.dump());
    std::string msg = error_of(f.path);
    EXPECT_HAS(msg, "'mm_per_unit' must be within 0.001..100000") << bad;
  }
  fs::remove(sidecar_path(f.path));
  for (double bad : {-1.0, std::nan(""), 1e300}) {
    GlassesOptions o;
    o.mm_per_unit = bad;
    EXPECT_HAS(error_of(f.path, o), "--mm-per-unit (Python: mm_per_unit) must be within 0.001..100000");
  }
  GlassesOptions detect;  // 0: detect the units (metres for this .glb)
  EXPECT_DOUBLE_EQ(load_glasses(f.path, detect).canonical.mm_per_unit, 1000.0);
}

TEST(RefPointsSidecar, TextRoundTrips) {
  FrameFile f;
  RefPointsSidecar s = f.sidecar;
  s.mm_per_unit = 25.4;
  RefPointsSidecar back = parse_refpoints_sidecar(refpoints_sidecar_text(s), "x.refpoints.json");
  EXPECT_EQ(back.points.g_l, s.points.g_l);
  EXPECT_EQ(back.points.g_r, s.points.g_r);
  EXPECT_EQ(back.mm_per_unit, 25.4);
  EXPECT_THROW(parse_refpoints_sidecar("[1, 2]", "x.refpoints.json"), std::runtime_error);
}

}  // namespace
}  // namespace lorgnette::mesh
