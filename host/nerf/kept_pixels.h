// The training pixels a set of views keeps when some carry ignore regions (View::ignore: polygons of
// things present in that view only, e.g. a held card), as runs of consecutive global pixel indices
// (the pixel order of DeviceViews: image after image, row after row). The sampler draws a kept index k
// uniformly and maps it to its global pixel through the runs (kernels/train/sampling.cl), so every
// ray of a batch lands on a kept pixel and the batch stays full. A pixel is ignored when its centre
// lies inside one of its view's polygons (even-odd rule per polygon, the union over polygons).
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace lorgnette::nerf {

using IgnorePolygon = std::vector<Eigen::Vector2f>;  // continuous pixels, centres at i + 0.5

// Per row of a width x height image, the ignored pixels' columns as half-open [begin, end) spans,
// sorted and disjoint (rows without any: empty). Pixel (x, y) is ignored when x + 0.5, y + 0.5 lies
// inside a polygon.
std::vector<std::vector<std::pair<int, int>>> ignored_spans(const std::vector<IgnorePolygon>& polygons,
                                                            int width, int height);

struct KeptPixels {
  // Pairs (first kept index of the run, its first global pixel), sorted; empty when nothing is
  // ignored (then kept index == global pixel and the sampler needs no table).
  std::vector<uint32_t> runs;
  uint64_t kept = 0;     // pixels kept over all views
  uint64_t ignored = 0;  // pixels left out
};

// sizes: (width, height) per view; ignore: per view, its polygons (may be empty). Throws
// std::runtime_error when every pixel is ignored (nothing to train on).
KeptPixels kept_pixel_runs(const std::vector<std::pair<int, int>>& sizes,
                           const std::vector<const std::vector<IgnorePolygon>*>& ignore);

}  // namespace lorgnette::nerf
