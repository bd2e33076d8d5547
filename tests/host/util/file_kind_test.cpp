// The one whole-file reader of the file formats (host/util/file_kind.h read_regular_file): it gives
// a file's bytes exactly (NULs and all), and refuses a directory, a FIFO (without blocking on it)
// and a missing or unreadable file with a message that names the file and what it was meant to be.
#include "host/util/file_kind.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>

#include "tests/common/text_and_errors.h"

namespace lorgnette {
namespace {
namespace fs = std::filesystem;
using lorgnette::testing::error_of;

fs::path fresh() {
  fs::path p = fs::path(LORGNETTE_TEST_TMP) / "file_kind";
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

TEST(ReadRegularFile, GivesTheBytesExactly) {
  const fs::path f = fresh() / "bytes.bin";
  const std::string bytes("head\0\xff\x01tail\n", 11);
  std::ofstream(f, std::ios::binary) << bytes;
  EXPECT_EQ(read_regular_file(f.string(), "model file"), bytes);
  std::ofstream(f, std::ios::binary | std::ios::trunc).flush();
  EXPECT_EQ(read_regular_file(f.string(), "model file"), "");  // empty: the parser says what is wrong
}

TEST(ReadRegularFile, RefusesWhatIsNoReadableFile) {
  const fs::path dir = fresh();
  std::string e = error_of([&] { read_regular_file(dir.string(), "sidecar"); });
  EXPECT_NE(e.find("sidecar '" + dir.string() + "' is a directory"), std::string::npos) << e;

  const fs::path fifo = dir / "pipe";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  e = error_of([&] { read_regular_file(fifo.string(), "mesh file"); });  // returns: no writer needed
  EXPECT_NE(e.find("is a FIFO"), std::string::npos) << e;

  const fs::path missing = dir / "missing.lnerf";
  e = error_of([&] { read_regular_file(missing.string(), "model file"); });
  EXPECT_NE(e.find("cannot open model file '" + missing.string() + "'"), std::string::npos) << e;

  if (geteuid() != 0) {  // root reads a file whatever its mode
    const fs::path locked = dir / "locked.json";
    std::ofstream(locked) << "{}";
    fs::permissions(locked, fs::perms::none);
    e = error_of([&] { read_regular_file(locked.string(), "dataset file"); });
    EXPECT_NE(e.find("cannot open dataset file"), std::string::npos) << e;
  }
}

}  // namespace
}  // namespace lorgnette
