// placement.json as `lorgnette render` reads it, on the viewer tests' tiny trained head and its
// fitted frame (tests/viewer/make_fixture.sh): a placement written with a relative glasses path in
// one working directory renders from another with `--placement` alone; a broken transform is
// refused with the field named; a placement used with another frame than the one fitted warns.
// Each render is one 32x32 view (about a second).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "fit/placement_json.h"
#include "tests/common/cli_run.h"

namespace lorgnette::fit {
namespace {

namespace fs = std::filesystem;
const fs::path kFixture = fs::path(LORGNETTE_TEST_TMP) / "viewer-fixture";

using lorgnette::testing::CliResult;

// `lorgnette render MODEL <args> --orbit 1 --size 32x32 --no-video --json -o out` run in `dir`;
// its summary goes to dir/summary.json.
CliResult render(const fs::path& dir, const std::string& args) {
  lorgnette::testing::CliCall call;
  call.stdout_to = "summary.json";
  return lorgnette::testing::run_cli(LGN_CLI_PATH, dir,
                                     "render '" + (kFixture / "head.lnerf").string() + "' " + args +
                                         " --orbit 1 --size 32x32 --no-video --force --json -o out",
                                     call);
}

class PlacementRender : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(kFixture / ".complete"))
      GTEST_SKIP() << "the viewer fixture is missing: run ctest -R viewer_fixture";
    root_ = fs::path(LORGNETTE_TEST_TMP) / "placement_render" /
            ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(root_);
    fs::create_directories(root_ / "work" / "frames");
    fs::create_directories(root_ / "work" / "out");
    fs::create_directories(root_ / "elsewhere");
    fs::copy_file(kFixture / "catalogue" / "a-round.glb", root_ / "work" / "frames" / "a-round.glb");
    fs::copy_file(kFixture / "catalogue" / "a-round.glb.refpoints.json",
                  root_ / "work" / "frames" / "a-round.glb.refpoints.json");
    fitted_ = read_placement((kFixture / "catalogue" / "a-round.glb.placement.json").string());
  }
  fs::path root_;
  PlacementFile fitted_;
};

TEST_F(PlacementRender, APlacementAloneRendersFromAnotherDirectory) {
  // As `lorgnette fit --glasses frames/a-round.glb -o out/placement.json` run in `work` writes it.
  const fs::path before = fs::current_path();
  ASSERT_EQ(::chdir((root_ / "work").c_str()), 0);
  PlacementFile p = fitted_;
  p.glasses_path = "frames/a-round.glb";
  write_placement("out/placement.json", p);
  ASSERT_EQ(::chdir(before.c_str()), 0);
  CliResult r = render(root_ / "elsewhere", "--placement ../work/out/placement.json");
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream summary(root_ / "elsewhere" / "summary.json");
  nlohmann::json j = nlohmann::json::parse(summary);
  EXPECT_TRUE(j["glasses"].get<bool>()) << "rendered without the glasses";
  EXPECT_TRUE(fs::equivalent(root_ / "elsewhere" / j["glasses_path"].get<std::string>(),
                             root_ / "work" / "frames" / "a-round.glb"));
  EXPECT_EQ(r.err.find("another glasses file"), std::string::npos) << r.err;
}

TEST_F(PlacementRender, BrokenTransformsAreRefusedNotRenderedWithoutGlasses) {
  nlohmann::json j = to_json(fitted_);
  j["glasses"]["path"] = (root_ / "work" / "frames" / "a-round.glb").string();
  const std::pair<const char*, nlohmann::json> cases[] = {
      {"all zero", nlohmann::json::array({{0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 1}})},
      {"1e300 scale",
       nlohmann::json::array({{1e300, 0, 0, 0}, {0, 1e300, 0, 0}, {0, 0, 1e300, 0}, {0, 0, 0, 1}})},
      {"non-affine", nlohmann::json::array({{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 1, 1}})},
  };
  for (const auto& [name, t] : cases) {
    j["transform"] = t;
    std::ofstream(root_ / "elsewhere" / "broken.json") << j.dump();
    CliResult r = render(root_ / "elsewhere", "--placement broken.json");
    EXPECT_NE(r.status, 0) << name << " rendered";
    EXPECT_NE(r.err.find("transform"), std::string::npos) << name << ": " << r.err;
  }
}

TEST_F(PlacementRender, AnotherFrameThanTheFittedOneWarns) {
  fs::copy_file(kFixture / "catalogue" / "b-rect.glb", root_ / "work" / "frames" / "b-rect.glb");
  const fs::path placement = kFixture / "catalogue" / "a-round.glb.placement.json";
  CliResult r = render(root_ / "elsewhere",
                       "--glasses ../work/frames/b-rect.glb --placement '" + placement.string() + "'");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("another glasses file"), std::string::npos) << r.err;
  r = render(root_ / "elsewhere",
             "--glasses ../work/frames/a-round.glb --placement '" + placement.string() + "'");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.find("another glasses file"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace lorgnette::fit
