// The output-folder rule (host/util/output_folder.h): --force replaces only an earlier output of
// the same command, never other files, the working directory or a folder holding an input; a staged
// output replaces the old one only on commit, and leaves it whole (and no staging folder) otherwise.
#include "host/util/output_folder.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "tests/common/text_and_errors.h"

namespace lorgnette {
namespace {
namespace fs = std::filesystem;

const OutputOwner kOwner{"synth", "synthetic dataset", ""};

fs::path fresh(const std::string& name) {
  fs::path p = fs::path(LORGNETTE_TEST_TMP) / "output_folder" / name;
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

using lorgnette::testing::error_of;
using lorgnette::testing::read;

// Names in `dir` that are not `keep`: staging or moved-aside folders left behind.
std::vector<std::string> leftovers(const fs::path& dir, const std::string& keep) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename() != keep) out.push_back(e.path().filename().string());
  return out;
}

TEST(OutputFolder, NewAndEmptyFoldersAreFreeWithoutForce) {
  fs::path root = fresh("free");
  EXPECT_FALSE(check_output_folder(root / "new", kOwner, false));
  fs::create_directories(root / "empty");
  EXPECT_FALSE(check_output_folder(root / "empty", kOwner, false));
}

TEST(OutputFolder, OtherFilesAreNeverReplacedEvenWithForce) {
  fs::path dir = fresh("other");
  std::ofstream(dir / "keep.txt") << "user data";
  std::string e = error_of([&] { check_output_folder(dir, kOwner, true); });
  EXPECT_NE(e.find("is not an earlier synthetic dataset"), std::string::npos) << e;
  EXPECT_NE(e.find("--force replaces only those"), std::string::npos) << e;
  // Another command's output is not this command's either.
  fs::path demo = fresh("other_command");
  mark_output(demo, {"demo", "demo output", ""});
  EXPECT_NE(error_of([&] { check_output_folder(demo, kOwner, true); }).find("not an earlier"),
            std::string::npos);
  EXPECT_THROW(StagedOutput(dir.string(), kOwner, true), std::runtime_error);
  EXPECT_EQ(read(dir / "keep.txt"), "user data");
}

TEST(OutputFolder, TheWorkingDirectoryAndFoldersAboveItAreRefused) {
  fs::path dir = fresh("cwd");
  fs::create_directories(dir / "inner");
  const fs::path before = fs::current_path();
  fs::current_path(dir / "inner");
  std::string here = error_of([&] { check_output_folder(".", kOwner, true); });
  std::string above = error_of([&] { check_output_folder("..", kOwner, true); });
  std::string staged = error_of([&] { StagedOutput s(".", kOwner, true); });
  fs::current_path(before);
  EXPECT_NE(here.find("working directory"), std::string::npos) << here;
  EXPECT_NE(above.find("working directory"), std::string::npos) << above;
  EXPECT_NE(staged.find("working directory"), std::string::npos) << staged;
  EXPECT_TRUE(fs::is_directory(dir / "inner"));
}

TEST(OutputFolder, AnInputInsideTheOutputIsRefusedUpFront) {
  fs::path dir = fresh("input_inside");
  mark_output(dir, kOwner);
  std::ofstream(dir / "frame.glb") << "glasses";
  std::string e =
      error_of([&] { StagedOutput s(dir.string(), kOwner, true, {(dir / "frame.glb").string()}); });
  EXPECT_NE(e.find("lies inside the output folder"), std::string::npos) << e;
  EXPECT_EQ(read(dir / "frame.glb"), "glasses");
  // An input beside the output is fine.
  std::ofstream(dir.parent_path() / "beside.glb") << "glasses";
  EXPECT_TRUE(check_output_folder(dir, kOwner, true, {(dir.parent_path() / "beside.glb").string()}));
}

TEST(OutputFolder, StagedOutputReplacesAnEarlierOutputOnlyOnCommit) {
  fs::path root = fresh("staged");
  const std::string dest = (root / "data").string();
  {
    StagedOutput first(dest, kOwner, false);
    EXPECT_FALSE(first.replaces_earlier());
    std::ofstream(fs::path(first.path()) / "a.txt") << "first";
    EXPECT_FALSE(fs::exists(dest)) << "nothing appears before commit";
    first.commit();
  }
  EXPECT_EQ(read(fs::path(dest) / "a.txt"), "first");
  EXPECT_TRUE(is_output_of(dest, kOwner));
  // Without --force an earlier output is refused, with the option named.
  std::string e = error_of([&] { StagedOutput s(dest, kOwner, false); });
  EXPECT_NE(e.find("--force"), std::string::npos) << e;
  // An interrupted run (no commit) leaves the old output whole and no staging folder.
  {
    StagedOutput second(dest, kOwner, true);
    EXPECT_TRUE(second.replaces_earlier());
    std::ofstream(fs::path(second.path()) / "a.txt") << "second";
  }
  EXPECT_EQ(read(fs::path(dest) / "a.txt"), "first");
  EXPECT_EQ(leftovers(root, "data"), std::vector<std::string>{});
  // A completed run replaces it: the new files only, nothing moved aside left behind.
  {
    StagedOutput third(dest, kOwner, true);
    std::ofstream(fs::path(third.path()) / "b.txt") << "third";
    third.commit();
  }
  EXPECT_FALSE(fs::exists(fs::path(dest) / "a.txt"));
  EXPECT_EQ(read(fs::path(dest) / "b.txt"), "third");
  EXPECT_EQ(leftovers(root, "data"), std::vector<std::string>{});
}

TEST(OutputFolder, LegacyMarkerRecognisesOutputsMadeBeforeTheMarker) {
  fs::path dir = fresh("legacy");
  std::ofstream(dir / "capture_report.json") << "{}";
  const OutputOwner capture{"capture", "capture", "capture_report.json"};
  EXPECT_TRUE(is_output_of(dir, capture));
  EXPECT_TRUE(check_output_folder(dir, capture, true));
  EXPECT_FALSE(is_output_of(dir, kOwner));
}

}  // namespace
}  // namespace lorgnette
