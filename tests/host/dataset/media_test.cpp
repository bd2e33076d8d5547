// Media outputs: the MP4 reopens with cv::VideoCapture with the right frame count, size and colours;
// an unfinished video leaves no file; the contact sheet has the documented size and the expected
// pixels at known cells; the error image shows the two inputs and the colour map at known errors.
#include "host/dataset/media.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <random>

#include "tests/common/scoped_tmpfs.h"

using namespace lorgnette;
using namespace lorgnette::dataset;
namespace fs = std::filesystem;

namespace {

fs::path fresh_dir(const std::string& name) {
  fs::path dir = fs::path(LORGNETTE_TEST_TMP) / "media" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

Image solid(int w, int h, float r, float g, float b) {
  Image img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      img.at(x, y, 0) = r;
      img.at(x, y, 1) = g;
      img.at(x, y, 2) = b;
    }
  return img;
}

}  // namespace

TEST(DatasetVideo, Mp4ReopensWithFrameCountSizeAndColours) {
  fs::path dir = fresh_dir("mp4");
  std::vector<Image> frames;
  for (int i = 0; i < 12; ++i) frames.push_back(solid(64, 48, i / 11.0f, 0.2f, 0.5f));
  std::string path = (dir / "orbit.mp4").string();
  std::string codec = write_mp4(path, frames, {});
  EXPECT_TRUE(codec == "avc1" || codec == "mp4v") << codec;
  cv::VideoCapture cap(path, cv::CAP_FFMPEG);
  ASSERT_TRUE(cap.isOpened());
  EXPECT_EQ(cap.get(cv::CAP_PROP_FRAME_COUNT), 12);
  EXPECT_EQ(cap.get(cv::CAP_PROP_FRAME_WIDTH), 64);
  EXPECT_EQ(cap.get(cv::CAP_PROP_FRAME_HEIGHT), 48);
  cv::Mat bgr;
  int decoded = 0;
  while (cap.read(bgr)) {
    cv::Scalar mean = cv::mean(bgr);
    float want_r = linear_to_srgb(decoded / 11.0f) * 255.0f, want_b = linear_to_srgb(0.5f) * 255.0f;
    // Lossy YUV 4:2:0 coding of flat colours: within 6 of 255 (limited-range rounding + quantisation).
    EXPECT_NEAR(mean[2], want_r, 6.0) << "frame " << decoded;
    EXPECT_NEAR(mean[0], want_b, 6.0) << "frame " << decoded;
    ++decoded;
  }
  EXPECT_EQ(decoded, 12);
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename(), "orbit.mp4");  // no temp left
}

TEST(DatasetVideo, OddSizeIsPaddedToEven) {
  fs::path dir = fresh_dir("odd");
  std::vector<Image> frames(3, solid(65, 49, 0.1f, 0.1f, 0.1f));
  write_mp4((dir / "odd.mp4").string(), frames);
  cv::VideoCapture cap((dir / "odd.mp4").string(), cv::CAP_FFMPEG);
  ASSERT_TRUE(cap.isOpened());
  EXPECT_EQ(cap.get(cv::CAP_PROP_FRAME_WIDTH), 66);
  EXPECT_EQ(cap.get(cv::CAP_PROP_FRAME_HEIGHT), 50);
}

TEST(DatasetVideo, BadInputsAndUnfinishedWriterLeaveNoFile) {
  fs::path dir = fresh_dir("bad");
  EXPECT_THROW(write_mp4((dir / "none.mp4").string(), {}), std::runtime_error);
  EXPECT_THROW(write_mp4("/nonexistent-dir-xyz/a.mp4", {solid(8, 8, 0, 0, 0)}), std::runtime_error);
  {
    Mp4Writer w((dir / "partial.mp4").string(), 32, 32);
    w.add(solid(32, 32, 1, 0, 0));
    EXPECT_THROW(w.add(solid(16, 32, 1, 0, 0)), std::runtime_error);
  }  // destroyed without finish(): interrupted
  EXPECT_TRUE(fs::is_empty(dir));
}

// A full disk: the encoder reports nothing, but a cut-short MP4 lacks its index and is refused;
// the contact sheet (an image write) throws too. Nothing is left under either name.
TEST(DatasetVideo, FullDiskIsAnErrorNotAShortVideo) {
  lgn_test::ScopedTmpfs disk(fs::path(LORGNETTE_TEST_TMP) / "media" / "full_disk", 48 * 1024);
  LGN_SKIP_UNLESS_MOUNTED(disk);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Image> noise;  // noise does not compress: 30 frames of 96x96 need far more than 48 KB
  for (int k = 0; k < 30; ++k) {
    Image img(96, 96, 3);
    for (float& v : img.pixels) v = u(rng);
    noise.push_back(std::move(img));
  }
  const fs::path video = disk.path() / "orbit.mp4";
  try {
    write_mp4(video.string(), noise);
    FAIL() << "a video larger than the disk must fail";
  } catch (const std::runtime_error& e) {
    std::printf("full disk: %s\n", e.what());
    EXPECT_NE(std::string(e.what()).find("orbit.mp4"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(video));
  disk.fill();
  const fs::path sheet = disk.path() / "contact_sheet.png";
  EXPECT_THROW(write_contact_sheet(sheet.string(), {noise[0], noise[1]}, {"a", "b"}), std::runtime_error);
  EXPECT_FALSE(fs::exists(sheet));
  for (const auto& e : fs::directory_iterator(disk.path()))
    EXPECT_EQ(e.path().filename(), "filler") << "left behind: " << e.path();
}

TEST(DatasetContactSheet, SizeAndCellPixels) {
  std::vector<Image> images;
  std::vector<std::string> labels;
  for (int i = 0; i < 5; ++i) {
    images.push_back(solid(40, 30, 0.1f * i, 0.5f, 1.0f - 0.1f * i));
    labels.push_back("view " + std::to_string(i));
  }
  ContactSheetOptions o;
  o.cell_width = 40;  // thumbnails at full size: exact pixel values
  o.padding = 4;
  o.label_height = 12;
  Image sheet = make_contact_sheet(images, labels, o);
  // 3 columns (ceil(sqrt(5))), 2 rows: W = 3*40 + 4*4, H = 2*(30 + 12) + 3*4.
  ASSERT_EQ(sheet.width, 136);
  ASSERT_EQ(sheet.height, 96);
  ASSERT_EQ(sheet.channels, 3);
  for (int i = 0; i < 5; ++i) {
    int cx = 4 + (i % 3) * 44 + 20, cy = 4 + (i / 3) * 46 + 15;
    EXPECT_FLOAT_EQ(sheet.at(cx, cy, 0), 0.1f * i) << "cell " << i;
    EXPECT_FLOAT_EQ(sheet.at(cx, cy, 2), 1.0f - 0.1f * i) << "cell " << i;
    // Label strip: some text pixels darker than the white background.
    float darkest = 1.0f;
    for (int y = cy + 15; y < cy + 27; ++y)
      for (int x = cx - 20; x < cx + 20; ++x) darkest = std::min(darkest, sheet.at(x, y, 1));
    EXPECT_LT(darkest, 0.5f) << "label " << i << " not drawn";
  }
  EXPECT_FLOAT_EQ(sheet.at(0, 0, 0), 1.0f);                      // padding = background
  EXPECT_FLOAT_EQ(sheet.at(4 + 2 * 44 + 20, 50 + 15, 0), 1.0f);  // empty 6th cell = background

  fs::path dir = fresh_dir("sheet");
  write_contact_sheet((dir / "sheet.png").string(), images, {}, o);
  Image back = read_image((dir / "sheet.png").string());
  EXPECT_EQ(back.width, 136);
  EXPECT_EQ(back.height, 2 * 30 + 3 * 4);  // no labels: no strips
  EXPECT_THROW(make_contact_sheet(images, {"one"}, o), std::runtime_error);
}

TEST(DatasetErrorImage, PanelsAndColourMap) {
  Image truth = solid(20, 10, 0.2f, 0.3f, 0.4f);  // sRGB + max_error stays below 1 (no clamping)
  Image pred = truth;
  // Pixel (3, 4): sRGB error of exactly max_error in every channel -> top of the colour map.
  ErrorImageOptions o;
  for (int c = 0; c < 3; ++c)
    pred.at(3, 4, c) = srgb_to_linear(linear_to_srgb(truth.at(3, 4, c)) + o.max_error);
  Image err = make_error_image(pred, truth, o);
  ASSERT_EQ(err.width, 60);
  ASSERT_EQ(err.height, 10);
  EXPECT_FLOAT_EQ(err.at(3, 4, 0), pred.at(3, 4, 0));
  EXPECT_FLOAT_EQ(err.at(20 + 3, 4, 0), truth.at(3, 4, 0));
  cv::Mat lv(1, 2, CV_8UC1), heat;
  lv.at<uint8_t>(0, 0) = 0;
  lv.at<uint8_t>(0, 1) = 255;
  cv::applyColorMap(lv, heat, cv::COLORMAP_INFERNO);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(err.at(40 + 0, 0, c), srgb_to_linear(heat.at<cv::Vec3b>(0, 0)[2 - c] / 255.0f), 1e-6);
    EXPECT_NEAR(err.at(40 + 3, 4, c), srgb_to_linear(heat.at<cv::Vec3b>(0, 1)[2 - c] / 255.0f), 1e-6);
  }
  EXPECT_LT(err.at(40, 0, 0), 0.01f);  // no error: near black
  EXPECT_GT(err.at(43, 4, 0), 0.8f);   // max error: bright yellow
  EXPECT_THROW(make_error_image(solid(5, 5, 0, 0, 0), truth), std::runtime_error);
}
