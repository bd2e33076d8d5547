// A dataset path that names a FIFO (or any file that is not a regular file) is refused with a clear
// message instead of blocking the reader: a model records its dataset's path, and by the time a
// `fit` or a `render` reads it back, anything may stand there.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <future>
#include <string>

#include "host/dataset/dataset.h"

namespace lorgnette::dataset {
namespace {

namespace fs = std::filesystem;

// Runs `f` on a thread; if it has not returned within 10 s (blocked on the FIFO), a writer opens
// the FIFO to release it and the test fails.
template <class F>
void without_blocking(const std::string& fifo, F&& f) {
  auto done = std::async(std::launch::async, std::forward<F>(f));
  if (done.wait_for(std::chrono::seconds(10)) != std::future_status::ready) {
    int fd = open(fifo.c_str(), O_WRONLY);  // lets the blocked reader see end-of-file
    if (fd >= 0) close(fd);
    ADD_FAILURE() << "reading '" << fifo << "' blocked";
  }
  done.get();
}

TEST(DatasetFifo, ATransformsFifoIsRefusedNotRead) {
  fs::path dir = fs::path(LORGNETTE_TEST_TMP) / "dataset_fifo";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string fifo = (dir / "transforms.json").string();
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& path : {fifo, dir.string()}) {  // the file itself, and its folder
    without_blocking(fifo, [&] {
      try {
        LoadOptions lo;
        lo.load_images = false;
        load_dataset(path, lo);
        ADD_FAILURE() << "loaded " << path;
      } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("is a FIFO (named pipe), not a regular file"), std::string::npos)
            << e.what();
      }
    });
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace lorgnette::dataset
