// The loader on the team's real datasets (read in place from LORGNETTE_DATA_DIR, never copied):
// NeRF-synthetic lego (RGBA, camera_angle_x, three splits), nerfstudio heads (OPENCV distortion,
// applied_transform, holdout every 8th frame), instant-ngp fox (aabb_scale, missing images).
// Expected values were read from the json files with Python's json module.
#include <gtest/gtest.h>

#include <filesystem>

#include "host/dataset/dataset.h"
#include "host/dataset/frame_image.h"

using namespace lorgnette;
using namespace lorgnette::dataset;
namespace fs = std::filesystem;

namespace {

std::string data_dir(const std::string& rel) { return std::string(LORGNETTE_DATA_DIR) + "/" + rel; }

#define SKIP_IF_ABSENT(dir) \
  if (!fs::exists(dir))     \
  GTEST_SKIP() << "test data '" << (dir) << "' is absent (see /work/shared/data/README.md)"

// Float intrinsics/poses are parsed from double: 1e-4 relative covers float32 rounding.
constexpr double kRel = 1e-6;

}  // namespace

TEST(DatasetRealData, LegoNerfSyntheticSplitsIntrinsicsAndAlpha) {
  std::string dir = data_dir("nerf/lego-400");
  SKIP_IF_ABSENT(dir);
  LoadOptions cams_only;
  cams_only.load_images = false;
  Dataset ds = load_dataset(dir, cams_only);
  EXPECT_EQ(ds.format, "nerf-synthetic");
  EXPECT_EQ(ds.split(Split::Train).size(), 100u);
  EXPECT_EQ(ds.split(Split::Val).size(), 100u);
  EXPECT_EQ(ds.split(Split::Test).size(), 200u);
  EXPECT_FALSE(ds.has_split(Split::Holdout));
  EXPECT_EQ(ds.default_eval_split(), Split::Test);
  const Frame& f0 = *ds.split(Split::Train)[0];
  EXPECT_EQ(f0.name, "r_0");
  EXPECT_EQ(f0.camera.width, 400u);
  EXPECT_NEAR(f0.camera.fx, 555.5555155968841, 555.6 * kRel);  // 200 / tan(camera_angle_x / 2)
  EXPECT_FLOAT_EQ(f0.camera.fy, f0.camera.fx);
  EXPECT_FLOAT_EQ(f0.camera.cx, 200.0f);
  EXPECT_FLOAT_EQ(f0.camera.c2w[3], -0.05379832163453102f);
  EXPECT_FLOAT_EQ(f0.camera.c2w[7], 3.845470428466797f);

  LoadOptions few;
  few.max_frames = 2;
  few.splits = {Split::Train};
  Dataset small = load_dataset(dir, few);
  ASSERT_EQ(small.frames.size(), 2u);
  EXPECT_TRUE(small.has_alpha);
  const Image& img = small.frames[0].image;
  ASSERT_EQ(img.width, 400);
  ASSERT_EQ(img.channels, 4);
  EXPECT_FLOAT_EQ(img.at(0, 0, 3), 0.0f);      // corner: transparent background
  EXPECT_FLOAT_EQ(img.at(200, 200, 3), 1.0f);  // centre: the lego model
}

TEST(DatasetRealData, In2nFaceHoldoutDistortionAndDownscale) {
  std::string dir = data_dir("heads/in2n-face");
  SKIP_IF_ABSENT(dir);
  LoadOptions cams_only;
  cams_only.load_images = false;
  Dataset ds = load_dataset(dir, cams_only);
  EXPECT_EQ(ds.format, "transforms");
  EXPECT_EQ(ds.split(Split::Holdout).size(), 9u);  // sorted indices 0, 8, ..., 64 of 65
  EXPECT_EQ(ds.split(Split::Train).size(), 56u);
  EXPECT_EQ(ds.default_eval_split(), Split::Holdout);
  const Frame& f0 = ds.frames[0];  // sorted by file path: frame_00001 first, held out
  EXPECT_EQ(f0.name, "frame_00001");
  EXPECT_EQ(f0.split, Split::Holdout);
  EXPECT_NEAR(f0.camera.fx, 533.9526178477054, 534 * kRel);
  EXPECT_NEAR(f0.camera.cy, 234.8048496174526, 235 * kRel);
  EXPECT_NEAR(f0.camera.k1, 0.011945461478577089, 1e-9);
  EXPECT_NEAR(f0.camera.p1, -0.004007237996032348, 1e-9);
  EXPECT_FLOAT_EQ(f0.camera.c2w[7], 4.5525548920985495f);
  EXPECT_TRUE(ds.has_applied_transform);

  LoadOptions half;
  half.downscale = 2;
  half.max_frames = 1;
  half.splits = {Split::Holdout};
  Dataset small = load_dataset(dir, half);
  ASSERT_EQ(small.frames.size(), 1u);
  EXPECT_EQ(small.frames[0].image.width, 256);
  EXPECT_EQ(small.frames[0].camera.width, 256u);
  EXPECT_NEAR(small.frames[0].camera.fx, 533.9526178477054 / 2, 267 * kRel);
  EXPECT_NEAR(small.frames[0].camera.cx, 261.55540683787973 / 2, 131 * kRel);
  EXPECT_FALSE(small.has_alpha);
  EXPECT_FLOAT_EQ(small.frames[0].image.at(10, 10, 3), 1.0f);
}

TEST(DatasetRealData, FangzhouAppliedTransformKept) {
  std::string dir = data_dir("heads/fangzhou-frontal");
  SKIP_IF_ABSENT(dir);
  LoadOptions cams_only;
  cams_only.load_images = false;
  Dataset ds = load_dataset(dir, cams_only);
  EXPECT_EQ(ds.split(Split::Holdout).size(), 13u);
  EXPECT_EQ(ds.split(Split::Train).size(), 87u);
  ASSERT_TRUE(ds.has_applied_transform);
  Eigen::Matrix4d expected;
  expected << 1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1;
  EXPECT_TRUE(ds.applied_transform.isApprox(expected)) << ds.applied_transform;
  EXPECT_NEAR(ds.frames[0].camera.fy, 682.6850943097463, 683 * kRel);
  EXPECT_FLOAT_EQ(ds.frames[0].camera.c2w[4], 0.03599196681039598f);
}

TEST(DatasetRealData, FoxMissingImagesAabbScaleAndMaxSide) {
  std::string dir = data_dir("nerf/fox");
  SKIP_IF_ABSENT(dir);
  // fox lists 67 frames for 50 photos: the 17 without one are skipped (with a warning), by default.
  LoadOptions lenient;
  lenient.load_images = false;
  Dataset ds = load_dataset(dir, lenient);
  EXPECT_EQ(ds.frames.size(), 50u);
  EXPECT_EQ(ds.split(Split::Holdout).size(), 8u);
  EXPECT_FLOAT_EQ(ds.aabb_scale, 4.0f);
  EXPECT_FALSE(ds.has_applied_transform);
  EXPECT_FLOAT_EQ(ds.frames[0].camera.c2w[4], 0.4464189982715247f);

  LoadOptions one = lenient;
  one.load_images = true;
  one.max_side = 480;  // 1080x1920 -> 270x480, scale exactly 1/4
  one.max_frames = 1;
  one.splits = {Split::Holdout};
  Dataset small = load_dataset(dir, one);
  ASSERT_EQ(small.frames.size(), 1u);
  EXPECT_EQ(small.frames[0].image.width, 270);
  EXPECT_EQ(small.frames[0].image.height, 480);
  EXPECT_NEAR(small.frames[0].camera.fx, 1375.52 / 4, 344 * kRel);
  EXPECT_NEAR(small.frames[0].camera.cy, 965.268 / 4, 242 * kRel);
}

// The loader's fast 8-bit path must give bitwise the pixels of image_io's read_image.
TEST(DatasetRealData, FastByteDecodeMatchesReadImage) {
  for (const char* rel : {"nerf/lego-400/train/r_0.png", "heads/in2n-face/images/frame_00001.jpg"}) {
    std::string path = data_dir(rel);
    if (!fs::exists(path)) GTEST_SKIP() << "test data '" << path << "' is absent";
    bool alpha = false;
    Image fast = detail::read_rgba(path, &alpha);
    Image ref = read_image(path);
    ASSERT_EQ(fast.width, ref.width);
    ASSERT_EQ(fast.height, ref.height);
    EXPECT_EQ(alpha, ref.channels == 4) << rel;
    size_t n = static_cast<size_t>(ref.width) * ref.height, mismatches = 0;
    for (size_t p = 0; p < n; ++p)
      for (int c = 0; c < ref.channels; ++c)
        mismatches += fast.pixels[p * 4 + c] != ref.pixels[p * ref.channels + c];
    EXPECT_EQ(mismatches, 0u) << rel;
  }
}
