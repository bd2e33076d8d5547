// nerfstudio's per-frame `mask_path` (0 = background) read as the frames' alpha: on a tiny dataset
// with 8-bit, 0/1 and 16-bit mask files the loaded alpha equals the mask value for value (and the
// image's own alpha times it), downscaling keeps the matte's coverage, and a missing mask, a mask of
// another size, a mask on only some frames or a mask_path that is not a string are refused with
// messages naming the frame and saying what to do.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "host/dataset/dataset.h"

using namespace lorgnette;
using namespace lorgnette::dataset;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr int kW = 16, kH = 12;

Camera ring_camera(int i) {
  Camera c{};
  c.fx = c.fy = 20.0f;
  c.cx = 8.0f;
  c.cy = 6.0f;
  c.width = kW;
  c.height = kH;
  double a = 0.3 * i, ca = std::cos(a), sa = std::sin(a);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() << ca, 0, sa, 0, 1, 0, -sa, 0, ca;
  m.block<3, 1>(0, 3) << 3 * sa, 0.0, 3 * ca;
  set_camera_pose(c, m);
  return c;
}

// The mask value of pixel (x, y) of frame i: a ramp over 0..255 with a background corner of zeros.
uint8_t mask_value(int i, int x, int y) {
  return x < 3 && y < 3 ? 0 : uint8_t((x * 16 + y * 7 + i * 31) % 256);
}

// Writes a single-channel mask of w x h in `type` (UINT8 or UINT16) with values v(x, y).
template <class V>
void write_mask(const fs::path& path, int w, int h, OIIO::TypeDesc type, V v) {
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out) << OIIO::geterror();
  OIIO::ImageSpec spec(w, h, 1, type);
  ASSERT_TRUE(out->open(path.string(), spec));
  std::vector<float> px(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) px[size_t(y) * w + x] = v(x, y);
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
  out->close();
}

// A dataset of n RGB frames with masks/m_<i>.png (8-bit ramp); `edit` may change the json after.
fs::path make_masked(const std::string& name, int n, const std::function<void(json&)>& edit = {}) {
  fs::path dir = fs::path(LORGNETTE_TEST_TMP) / "dataset_masks" / name;
  fs::remove_all(dir);
  fs::create_directories(dir / "images");
  fs::create_directories(dir / "masks");
  std::vector<Camera> cams;
  std::vector<std::string> files;
  for (int i = 0; i < n; ++i) {
    std::string file = "images/f_" + std::to_string(i) + ".png";
    write_image((dir / file).string(), Image(kW, kH, 3, 0.5f));
    write_mask(dir / "masks" / ("m_" + std::to_string(i) + ".png"), kW, kH, OIIO::TypeDesc::UINT8,
               [i](int x, int y) { return mask_value(i, x, y) / 255.0f; });
    cams.push_back(ring_camera(i));
    files.push_back(file);
  }
  write_transforms_json(dir.string(), cams, files);
  std::ifstream in(dir / "transforms.json");
  json doc = json::parse(in);
  for (auto& f : doc["frames"]) {
    std::string stem = fs::path(f["file_path"].get<std::string>()).stem().string();  // f_<i>
    f["mask_path"] = "masks/m_" + stem.substr(2) + ".png";
  }
  if (edit) edit(doc);
  std::ofstream(dir / "transforms.json") << doc.dump(1);
  return dir;
}

std::string load_error(const fs::path& dir, LoadOptions opt = {}) {
  try {
    load_dataset(dir.string(), opt);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

#define EXPECT_HAS(msg, text) EXPECT_NE((msg).find(text), std::string::npos) << "message: " << (msg)

TEST(DatasetMasks, AlphaEqualsTheMask) {
  fs::path dir = make_masked("ramp", 3);
  Dataset ds = load_dataset(dir.string());
  EXPECT_TRUE(ds.has_alpha);
  ASSERT_EQ(ds.frames.size(), 3u);
  for (const Frame& f : ds.frames) {
    int i = std::stoi(f.name.substr(2));
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        // OIIO's byte -> float is v / 255 to within an ulp.
        ASSERT_NEAR(f.image.at(x, y, 3), mask_value(i, x, y) / 255.0f, 1e-6f)
            << f.name << " " << x << "," << y;
        ASSERT_NEAR(f.image.at(x, y, 0), f.image.at(0, 0, 0), 0.0f);  // colour untouched
      }
    EXPECT_TRUE(f.image.has_transparency());
  }
  // Cameras-only loads check the masks too, and say the dataset has alpha.
  LoadOptions cams_only;
  cams_only.load_images = false;
  EXPECT_TRUE(load_dataset(dir.string(), cams_only).has_alpha);
}

TEST(DatasetMasks, BinaryAndSixteenBitMasksAndDownscaling) {
  fs::path dir = make_masked("formats", 2);
  // Frame 0: a 0/1 mask in 8 bits (nerfstudio's bool semantics); frame 1: a 16-bit mask.
  write_mask(dir / "masks" / "m_0.png", kW, kH, OIIO::TypeDesc::UINT8,
             [](int x, int) { return x >= 8 ? 1.0f / 255.0f : 0.0f; });
  write_mask(dir / "masks" / "m_1.png", kW, kH, OIIO::TypeDesc::UINT16,
             [](int x, int) { return x >= 8 ? 40000.0f / 65535.0f : 0.0f; });
  Dataset ds = load_dataset(dir.string());
  const Frame& f0 = ds.frames[0].name == "f_0" ? ds.frames[0] : ds.frames[1];
  const Frame& f1 = ds.frames[0].name == "f_0" ? ds.frames[1] : ds.frames[0];
  EXPECT_EQ(f0.image.at(3, 4, 3), 0.0f);
  EXPECT_EQ(f0.image.at(12, 4, 3), 1.0f);
  EXPECT_NEAR(f1.image.at(12, 4, 3), 40000.0f / 65535.0f, 1e-6f);
  EXPECT_EQ(f1.image.at(3, 4, 3), 0.0f);
  // Downscaled by 2: the half-covered image keeps half its coverage (area averaging).
  LoadOptions half;
  half.downscale = 2;
  Dataset small = load_dataset(dir.string(), half);
  const Frame& s0 = small.frames[0].name == "f_0" ? small.frames[0] : small.frames[1];
  double sum = 0;
  for (int y = 0; y < s0.image.height; ++y)
    for (int x = 0; x < s0.image.width; ++x) sum += s0.image.at(x, y, 3);
  EXPECT_NEAR(sum / (s0.image.width * s0.image.height), 0.5, 1e-6);
}

TEST(DatasetMasks, RgbaImagesKeepTheirAlphaTimesTheMask) {
  fs::path dir = make_masked("rgba", 2);
  write_image((dir / "images" / "f_0.png").string(), Image(kW, kH, 4, 0.5f));  // alpha 0.5 everywhere
  Dataset ds = load_dataset(dir.string());
  const Frame& f0 = ds.frames[0].name == "f_0" ? ds.frames[0] : ds.frames[1];
  // 8-bit alpha 0.5 is stored as 128 (or 127) / 255; tolerance one byte step.
  EXPECT_NEAR(f0.image.at(10, 5, 3), 0.5f * mask_value(0, 10, 5) / 255.0f, 1.0f / 255.0f);
}

TEST(DatasetMasks, BadMasksAreRefusedWithWhatToDo) {
  // A mask file that is not there.
  fs::path dir = make_masked("missing", 3);
  fs::remove(dir / "masks" / "m_1.png");
  std::string e = load_error(dir);
  EXPECT_HAS(e, "frame 1 ('images/f_1.png')");
  EXPECT_HAS(e, "masks/m_1.png");
  EXPECT_HAS(e, "not there");
  EXPECT_HAS(e, "remove 'mask_path' from every frame");
  LoadOptions cams_only;
  cams_only.load_images = false;
  EXPECT_HAS(load_error(dir, cams_only), "not there");
  // A mask of another size than its image.
  dir = make_masked("wrong_size", 3);
  write_mask(dir / "masks" / "m_2.png", kW / 2, kH / 2, OIIO::TypeDesc::UINT8, [](int, int) { return 1.0f; });
  e = load_error(dir);
  EXPECT_HAS(e, "frame 2");
  EXPECT_HAS(e, "is 8x6 but its image");
  EXPECT_HAS(e, "is 16x12");
  EXPECT_HAS(load_error(dir, cams_only), "is 8x6 but its image");
  // A mask that is not an image.
  dir = make_masked("corrupt", 3);
  std::ofstream(dir / "masks" / "m_0.png") << "not a png";
  EXPECT_HAS(load_error(dir), "replace the mask");
  // Masks on some frames only (nerfstudio's rule: every frame or none).
  dir = make_masked("some", 3, [](json& d) { d["frames"][1].erase("mask_path"); });
  e = load_error(dir);
  EXPECT_HAS(e, "2 of 3 frames have a 'mask_path'");
  EXPECT_HAS(e, "give every frame a mask");
  // Not a string.
  dir = make_masked("number", 3, [](json& d) { d["frames"][0]["mask_path"] = 7; });
  EXPECT_HAS(load_error(dir), "'mask_path' must name a mask image");
}

}  // namespace
