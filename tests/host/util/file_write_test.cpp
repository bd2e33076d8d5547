// Every write is checked (host/util/file_write.h, image_io.h): on a full disk or a read-only folder
// (a small tmpfs the test mounts) a write throws with the reason, the earlier file stays as it was,
// and no empty or temporary file is left; on a normal folder PNG and EXR round-trip.
#include "host/util/file_write.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "host/util/image_io.h"
#include "tests/common/scoped_tmpfs.h"
#include "tests/common/text_and_errors.h"

namespace lorgnette {
namespace {
namespace fs = std::filesystem;
using lgn_test::ScopedTmpfs;

fs::path fresh(const std::string& name) {
  fs::path p = fs::path(LORGNETTE_TEST_TMP) / "file_write" / name;
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

// A mount point for ScopedTmpfs (which clears it itself).
fs::path mount_dir(const std::string& name) { return fs::path(LORGNETTE_TEST_TMP) / "file_write" / name; }

using lorgnette::testing::error_of;
using lorgnette::testing::read;

// Every file in `dir` other than the tmpfs filler and `keep`.
std::vector<std::string> others(const fs::path& dir, const std::string& keep = "") {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::string n = e.path().filename().string();
    if (n != "filler" && n != keep) out.push_back(n);
  }
  return out;
}

Image gradient(int w, int h, int channels) {
  Image img(w, h, channels);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < channels; ++c) img.at(x, y, c) = float((x * 7 + y * 3 + c * 50) % 256) / 255.0f;
  return img;
}

TEST(FileWrite, FullDiskThrowsAndKeepsTheEarlierFile) {
  ScopedTmpfs disk(mount_dir("full_text"), 64 * 1024);
  LGN_SKIP_UNLESS_MOUNTED(disk);
  const fs::path target = disk.path() / "placement.json";
  write_file_atomic(target.string(), "earlier");
  disk.fill();
  std::string e = error_of([&] { write_file_atomic(target.string(), std::string(20000, 'n')); });
  EXPECT_NE(e.find("No space left on device"), std::string::npos) << e;
  EXPECT_NE(e.find("placement.json"), std::string::npos) << e;
  EXPECT_EQ(read(target), "earlier");
  EXPECT_EQ(others(disk.path(), "placement.json"), std::vector<std::string>{});
  // write_text_file_atomic (JSON, CSV, the .lnerf snapshot) goes the same way.
  EXPECT_THROW(write_text_file_atomic(target.string(), std::string(20000, 'n')), std::runtime_error);
  EXPECT_EQ(read(target), "earlier");
}

TEST(FileWrite, ImagesOnAFullDiskThrowAndLeaveNoEmptyFile) {
  ScopedTmpfs disk(mount_dir("full_images"), 64 * 1024);
  LGN_SKIP_UNLESS_MOUNTED(disk);
  disk.fill();
  for (const char* name : {"frame_0000.png", "depth_0000.exr", "photo.jpg"}) {
    const fs::path p = disk.path() / name;
    std::string e = error_of([&] { write_image(p.string(), gradient(64, 48, 3)); });
    EXPECT_NE(e.find("No space left on device"), std::string::npos) << name << ": " << e;
    EXPECT_FALSE(fs::exists(p)) << name;
  }
  EXPECT_EQ(others(disk.path()), std::vector<std::string>{});
}

TEST(FileWrite, ImagesRoundTripThroughTheCheckedWriter) {
  fs::path dir = fresh("round_trip");
  Image rgb = gradient(33, 17, 3);
  write_image((dir / "a.png").string(), rgb);
  Image png = read_image((dir / "a.png").string());
  ASSERT_EQ(png.width, 33);
  ASSERT_EQ(png.channels, 3);
  // 8-bit sRGB: within half a code of the linear value's encoding (plus float rounding).
  for (size_t i = 0; i < rgb.pixels.size(); ++i)
    ASSERT_NEAR(linear_to_srgb(png.pixels[i]), linear_to_srgb(rgb.pixels[i]), 0.5f / 255.0f + 1e-5f) << i;
  Image depth = gradient(9, 5, 1);
  depth.at(2, 2, 0) = INFINITY;
  write_image((dir / "d.exr").string(), depth);
  Image exr = read_image((dir / "d.exr").string());
  ASSERT_EQ(exr.pixels.size(), depth.pixels.size());
  for (size_t i = 0; i < depth.pixels.size(); ++i) EXPECT_EQ(exr.pixels[i], depth.pixels[i]) << i;
  EXPECT_EQ(others(dir, "a.png").size(), 1u) << "only a.png and d.exr, no temporary files";
}

TEST(FileWrite, WritableFolderCheckFindsReadOnlyAndFullDisks) {
  fs::path ok = fresh("writable");
  EXPECT_NO_THROW(check_writable_folder(ok.string(), "the model"));
  EXPECT_EQ(others(ok), std::vector<std::string>{}) << "the probe file is removed";
  std::string missing = error_of([&] { check_writable_folder((ok / "nope").string(), "the model"); });
  EXPECT_NE(missing.find("does not exist"), std::string::npos) << missing;

  ScopedTmpfs read_only(mount_dir("read_only"), 64 * 1024, true);
  LGN_SKIP_UNLESS_MOUNTED(read_only);
  std::string ro = error_of([&] { check_writable_folder(read_only.path().string(), "the model"); });
  EXPECT_NE(ro.find("Read-only file system"), std::string::npos) << ro;
  EXPECT_NE(ro.find("the model"), std::string::npos) << ro;

  ScopedTmpfs full(mount_dir("full_probe"), 64 * 1024);
  LGN_SKIP_UNLESS_MOUNTED(full);
  full.fill();
  std::string e = error_of([&] { check_writable_folder(full.path().string(), "the model"); });
  EXPECT_NE(e.find("No space left on device"), std::string::npos) << e;
  EXPECT_EQ(others(full.path()), std::vector<std::string>{});
}

// The order of the system calls is the rule (file data on disk before its new name, the name on disk
// after the rename), so the test traces them: this test binary runs itself under strace, in a mode
// where it only writes one file, and reads the trace. Skipped where strace is missing or ptrace is not
// allowed (some containers).
TEST(FileWrite, SyncsTheFileBeforeTheRenameAndTheFolderAfter) {
  if (const char* target = std::getenv("LGN_FILE_WRITE_ONCE")) {  // the traced child
    write_file_atomic(target, "durable");
    return;
  }
  fs::path dir = fresh("fsync");
  const fs::path target = dir / "out.txt", trace = dir / "trace.txt";
  const std::string cmd =
      "LGN_FILE_WRITE_ONCE='" + target.string() +
      "' strace -f -qq -e trace=fsync,rename,renameat,renameat2 -o '" + trace.string() + "' /proc/" +
      std::to_string(getpid()) +
      "/exe --gtest_filter=FileWrite.SyncsTheFileBeforeTheRenameAndTheFolderAfter > /dev/null 2>&1";
  if (std::system(cmd.c_str()) != 0 || !fs::exists(trace))
    GTEST_SKIP() << "strace is missing or may not trace here; the fsync order is not checked";
  ASSERT_EQ(read(target), "durable");
  // One line per call: "PID fsync(3) = 0", "PID rename(\".../.out.PID.tmp.txt\", \".../out.txt\") = 0".
  std::istringstream lines(read(trace));
  std::string line;
  int fsyncs_before = 0, fsyncs_after = 0;
  bool renamed = false;
  while (std::getline(lines, line)) {
    if (line.find("rename") != std::string::npos && line.find(target.string() + "\"") != std::string::npos)
      renamed = true;
    else if (line.find("fsync(") != std::string::npos && line.find("= 0") != std::string::npos)
      ++(renamed ? fsyncs_after : fsyncs_before);
  }
  EXPECT_TRUE(renamed) << read(trace);
  EXPECT_EQ(fsyncs_before, 1) << "the file is synced before its rename:\n" << read(trace);
  EXPECT_EQ(fsyncs_after, 1) << "the folder is synced after the rename:\n" << read(trace);
}

}  // namespace
}  // namespace lorgnette
