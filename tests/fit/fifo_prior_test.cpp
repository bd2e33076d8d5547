// A model whose dataset_path names a FIFO must not block `fit`. The fit reads the capture's
// cameras for its view prior from that path (fit_job.cpp); a FIFO there is skipped with a warning
// (as a missing file is) instead of being opened, which would wait forever for a writer.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <future>

#include "fit/nerf_view_source.h"
#include "host/nerf/model.h"

namespace lorgnette::fit {
namespace {

namespace fs = std::filesystem;

TEST(FitPrior, AFifoAsTheModelsDatasetIsSkippedNotOpened) {
  fs::path dir = fs::path(LORGNETTE_TEST_TMP) / "fit_fifo";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string fifo = (dir / "transforms.json").string();
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  cl::Runtime rt({"", "", false});
  field::FieldConfig config;
  config.log2_table_size = 10;
  config.finest_resolution = 32;
  nerf::NerfModel model(rt, config, {{-1, -1, -1}, {1, 1, 1}}, 16, 0.01f, 256, 1, true);
  model.metadata.dataset_path = dir.string();
  auto done = std::async(std::launch::async, [&] { return prior_from_transforms(fifo, model); });
  if (done.wait_for(std::chrono::seconds(10)) != std::future_status::ready) {
    int fd = open(fifo.c_str(), O_WRONLY);  // release the blocked reader, then fail
    if (fd >= 0) close(fd);
    ADD_FAILURE() << "the fit's prior blocked on a FIFO";
  }
  ViewPrior prior = done.get();
  EXPECT_FALSE(prior.front.has_value());  // no cameras read: the default prior
  EXPECT_FALSE(prior.target.has_value());
  EXPECT_TRUE(prior.up == ViewPrior{}.up);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace lorgnette::fit
