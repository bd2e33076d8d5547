// ignore_regions.json (host/dataset/ignore_regions.h): written and read back exactly, absent = no
// region; load_dataset puts each frame's polygons on it, scaled with its intrinsics when the images
// are shrunk; a malformed file, a polygon of two vertices, a frame listed twice or one the dataset
// does not have, and regions drawn on an image of another shape are refused with what to do.
#include "host/dataset/ignore_regions.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "host/dataset/dataset.h"
#include "tests/common/text_and_errors.h"
#include "tests/host/dataset/ring_dataset.h"

namespace lorgnette::dataset {
namespace {

namespace fs = std::filesystem;
constexpr int kW = 32, kH = 24;

// Three frames f_0..f_2 of kW x kH on a ring around the origin.
fs::path make_dataset(const std::string& name) {
  return lorgnette::testing::write_ring_dataset(fs::path(LORGNETTE_TEST_TMP) / "ignore_regions" / name, 3, kW,
                                                kH, 30.0f, 0.4);
}

IgnoreRegions sample_regions() {
  IgnoreRegions r;
  r.source = "card";
  r.margin_mm = 20.0;
  r.frames.push_back({"f_1", kW, kH, {{{2.5f, 3.0f}, {20.25f, 4.0f}, {18.0f, 15.5f}, {3.0f, 14.0f}}}});
  r.frames.push_back({"f_2", kW, kH, {{{0, 0}, {8, 0}, {4, 6}}, {{10, 10}, {30, 10}, {30, 20}, {10, 20}}}});
  return r;
}

std::string load_error(const fs::path& dir) {
  return lorgnette::testing::error_of([&] { load_dataset(dir.string()); });
}

#define EXPECT_HAS(text, part) EXPECT_NE((text).find(part), std::string::npos) << (text)

TEST(IgnoreRegionsFile, RoundTripsExactlyAndAbsentIsNone) {
  const fs::path dir = make_dataset("roundtrip");
  EXPECT_FALSE(read_ignore_regions(dir.string()).has_value());
  const IgnoreRegions r = sample_regions();
  write_ignore_regions(dir.string(), r);
  const auto back = read_ignore_regions(dir.string());
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->source, "card");
  EXPECT_EQ(back->margin_mm, 20.0);
  ASSERT_EQ(back->frames.size(), r.frames.size());
  for (size_t i = 0; i < r.frames.size(); ++i) {
    EXPECT_EQ(back->frames[i].name, r.frames[i].name);
    EXPECT_EQ(back->frames[i].width, kW);
    ASSERT_EQ(back->frames[i].polygons.size(), r.frames[i].polygons.size());
    for (size_t p = 0; p < r.frames[i].polygons.size(); ++p)
      EXPECT_EQ(back->frames[i].polygons[p], r.frames[i].polygons[p]);  // floats written in full
  }
}

TEST(IgnoreRegionsFile, TheLoaderPutsThemOnTheirFramesAtTheLoadedSize) {
  const fs::path dir = make_dataset("loader");
  const IgnoreRegions r = sample_regions();
  write_ignore_regions(dir.string(), r);
  const Dataset full = load_dataset(dir.string());
  LoadOptions half;
  half.downscale = 2;
  const Dataset small = load_dataset(dir.string(), half);
  for (const Dataset* ds : {&full, &small}) {
    const float s = float(ds->frames[0].camera.width) / kW;
    for (const Frame& f : ds->frames) {
      const FrameIgnore* listed = nullptr;
      for (const auto& fi : r.frames) listed = fi.name == f.name ? &fi : listed;
      ASSERT_EQ(f.ignore.size(), listed ? listed->polygons.size() : 0u) << f.name;
      for (size_t p = 0; p < f.ignore.size(); ++p)
        for (size_t v = 0; v < f.ignore[p].size(); ++v)
          EXPECT_NEAR((f.ignore[p][v] - s * listed->polygons[p][v]).norm(), 0.0f, 1e-5f);
    }
  }
  EXPECT_EQ(small.frames[0].camera.width, uint32_t(kW / 2));
}

TEST(IgnoreRegionsFile, BadFilesAreRefusedWithWhatToDo) {
  const fs::path dir = make_dataset("bad");
  auto write = [&](const std::string& text) { std::ofstream(dir / kIgnoreRegionsFile) << text; };
  write("not json");
  EXPECT_HAS(load_error(dir), "is not a JSON object");
  EXPECT_HAS(load_error(dir), "delete it");
  write(R"({"version": 2, "source": "card", "frames": []})");
  EXPECT_HAS(load_error(dir), "format version 2");
  write(R"({"version": 1, "source": "card"})");
  EXPECT_HAS(load_error(dir), "lacks a field");
  write(R"({"version": 1, "source": "card", "frames": [{"name": "f_1", "width": 32, "height": 24,
            "polygons": [[[1, 2], [3, 4]]]}]})");
  EXPECT_HAS(load_error(dir), "polygon of 2 vertices");
  write(R"({"version": 1, "source": "card", "frames": [{"name": "f_1", "width": 32, "height": 24,
            "polygons": [[[1, 2, 3], [3, 4], [5, 6]]]}]})");
  EXPECT_HAS(load_error(dir), "3 numbers, not 2");
  write(
      R"({"version": 1, "source": "card", "frames": [{"name": "f_1", "width": 32, "height": 24, "polygons": []},
            {"name": "f_1", "width": 32, "height": 24, "polygons": []}]})");
  EXPECT_HAS(load_error(dir), "listed twice");
  write(
      R"({"version": 1, "source": "card", "frames": [{"name": "g_7", "width": 32, "height": 24, "polygons": []}]})");
  EXPECT_HAS(load_error(dir), "names frame 'g_7', which the dataset does not list");
  write(R"({"version": 1, "source": "card", "frames": [{"name": "f_0", "width": 32, "height": 32,
            "polygons": [[[1, 2], [3, 4], [5, 9]]]}]})");
  EXPECT_HAS(load_error(dir), "another shape");
  IgnoreRegions r = sample_regions();
  r.frames[0].polygons[0][1].x() = NAN;
  EXPECT_THROW(write_ignore_regions(dir.string(), r), std::runtime_error);
}

}  // namespace
}  // namespace lorgnette::dataset
