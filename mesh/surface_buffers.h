// The surface pass's output and the compositing marcher's input (ARCHITECTURE.md "Surface
// buffers"): per pixel the glasses' colour S_c (linear RGB, premultiplied by coverage), coverage
// S_α in [0, 1] and depth S_t along the primary ray in scene units (+inf where no sample hit).
// Flat float arrays so they upload to the device as they are.
#pragma once
#include <cstdint>
#include <limits>
#include <vector>

namespace lorgnette::mesh {

struct SurfaceBuffers {
  int width = 0, height = 0;
  std::vector<float> color_alpha;  // 4 per pixel, row-major, top row first: S_c.rgb (premultiplied), S_α
  std::vector<float> depth;        // 1 per pixel: S_t, +inf where nothing was hit

  SurfaceBuffers() = default;
  SurfaceBuffers(int w, int h)
      : width(w), height(h), color_alpha(static_cast<size_t>(w) * h * 4, 0.0f),
        depth(static_cast<size_t>(w) * h, std::numeric_limits<float>::infinity()) {}
  size_t pixel_count() const { return static_cast<size_t>(width) * height; }
};

}  // namespace lorgnette::mesh
