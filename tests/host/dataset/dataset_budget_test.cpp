// LoadOptions::max_image_bytes: images that would hold more memory than the budget (linear float
// RGBA) are all shrunk by one factor until they fit, with their intrinsics, and images within it are
// loaded as they are; a max_side given with it still applies.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "host/dataset/dataset.h"
#include "tests/host/dataset/ring_dataset.h"

using namespace lorgnette;
using namespace lorgnette::dataset;
namespace fs = std::filesystem;

namespace {

constexpr int kW = 160, kH = 120, kFrames = 4;

// A dataset of kFrames grey RGB frames of kW x kH on a ring of cameras.
fs::path make_dataset() {
  return lorgnette::testing::write_ring_dataset(fs::path(LORGNETTE_TEST_TMP) / "dataset_budget", kFrames, kW,
                                                kH, 200.0f, 0.3);
}

uint64_t image_bytes(const Dataset& ds) {
  uint64_t bytes = 0;
  for (const Frame& f : ds.frames) bytes += f.image.pixels.size() * sizeof(float);
  return bytes;
}

TEST(DatasetBudget, ImagesOverTheBudgetShrinkToFitIt) {
  const fs::path dir = make_dataset();
  const uint64_t full = uint64_t(kFrames) * kW * kH * 16;  // 1.23 MB
  LoadOptions opt;
  for (uint64_t budget : {uint64_t(0), full, 2 * full}) {  // none, or one they fit
    opt.max_image_bytes = budget;
    const Dataset ds = load_dataset(dir.string(), opt);
    EXPECT_EQ(image_bytes(ds), full) << budget;
    EXPECT_EQ(ds.frames[0].camera.width, uint32_t(kW)) << budget;
  }
  // A third of it: every image shrinks by one factor (~0.57), to within the budget but not far below.
  opt.max_image_bytes = full / 3;
  const Dataset ds = load_dataset(dir.string(), opt);
  EXPECT_LE(image_bytes(ds), opt.max_image_bytes);
  EXPECT_GT(image_bytes(ds), opt.max_image_bytes * 9 / 10);
  for (const Frame& f : ds.frames) {
    EXPECT_EQ(f.image.width, ds.frames[0].image.width);
    EXPECT_EQ(f.camera.width, uint32_t(f.image.width));
    EXPECT_EQ(f.camera.height, uint32_t(f.image.height));
    EXPECT_NEAR(f.camera.fx, 200.0 * f.image.width / kW, 1e-3);  // intrinsics follow the size
    EXPECT_NEAR(f.image.pixels[0], 0.5f, 0.01f);                 // resampled (8-bit sRGB file), not cropped
  }
  EXPECT_LT(ds.frames[0].image.width, kW * 0.6);
  EXPECT_GT(ds.frames[0].image.width, kW * 0.5);
  // A max_side of its own still applies, and the budget on top of it.
  opt.max_side = 100;
  opt.max_image_bytes = 0;
  EXPECT_EQ(load_dataset(dir.string(), opt).frames[0].image.width, 100);
  opt.max_image_bytes = full / 10;
  const Dataset both = load_dataset(dir.string(), opt);
  EXPECT_LE(image_bytes(both), opt.max_image_bytes);
  EXPECT_LT(both.frames[0].image.width, 100);
  // Cameras only: nothing is loaded, so nothing shrinks.
  opt = {};
  opt.max_image_bytes = full / 3;
  opt.load_images = false;
  EXPECT_EQ(load_dataset(dir.string(), opt).frames[0].camera.width, uint32_t(kW));
}

}  // namespace
