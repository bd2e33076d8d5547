// A dataset's ignore regions, ignore_regions.json beside transforms.json: per frame, polygons in its
// image whose pixels show something that is not part of the static scene in that frame only (a held
// card and the fingers on it, written by `capture`), so training leaves them out of its loss. E.g.
//   {"version": 1, "source": "card", "margin_mm": 20,
//    "frames": [{"name": "0003", "width": 768, "height": 768,
//                "polygons": [[[410.5, 230.0], [505.0, 262.5], [530.0, 331.0], [430.0, 310.0]]]}]}
// Coordinates are continuous pixels (pixel centres at i + 0.5) of the image at width x height, the
// size the polygons were drawn on; load_dataset scales them with the frame's intrinsics when it
// shrinks the images. A pixel is ignored when its centre lies inside a polygon (even-odd rule).
// Frames not listed have no region. One owner of the format: this file.
#pragma once
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

namespace lorgnette::dataset {

inline constexpr const char* kIgnoreRegionsFile = "ignore_regions.json";

using IgnorePolygon = std::vector<Eigen::Vector2f>;  // >= 3 vertices, continuous pixels

struct FrameIgnore {
  std::string name;  // the frame's name (its image's file stem, dataset.h Frame::name)
  int width = 0;     // the image size the polygons are in
  int height = 0;
  std::vector<IgnorePolygon> polygons;
};

struct IgnoreRegions {
  std::string source;      // what the regions hide, e.g. "card"
  double margin_mm = 0.0;  // the writer's margin around the object (recorded for people; >= 0)
  std::vector<FrameIgnore> frames;
};

// Throws std::runtime_error naming the frame and value unless every frame has a name (no two alike),
// a positive size and polygons of >= 3 finite vertices.
void check_ignore_regions(const IgnoreRegions& r, const std::string& where);

void write_ignore_regions(const std::string& dataset_dir, const IgnoreRegions& r);

// Absent file: nullopt. Unreadable or malformed: std::runtime_error saying what is wrong and that
// deleting the file (or running `capture --card-only` again) trains on every pixel of every frame.
std::optional<IgnoreRegions> read_ignore_regions(const std::string& dataset_dir);

// `polygons`, drawn on a from_w x from_h image, for the same image resized to to_w x to_h (the
// per-axis ratio, as the intrinsics are scaled: dataset.h).
std::vector<IgnorePolygon> scale_polygons(const std::vector<IgnorePolygon>& polygons, int from_w, int from_h,
                                          int to_w, int to_h);

}  // namespace lorgnette::dataset
