// The surface pass's output (mesh/) and the compositing marcher's input (host/render), so it lives
// on the ground floor below both (ARCHITECTURE.md "Surface buffers"): per pixel the glasses' colour
// S_c (linear RGB, premultiplied by coverage), coverage S_α in [0, 1] and depth S_t along the primary ray in
// scene units (+inf where no sample hit), and the colour filter F of the light that passes (tinted lenses):
// what lies behind the surface is seen as T(t_s)·(1 − S_α)·F ⊙ C'. F is the per-channel transmittance divided
// by its mean (1 − S_α), so a grey lens or an opaque frame has F = 1. Flat float arrays so they upload to the
// device as they are.
#pragma once
#include <cstdint>
#include <limits>
#include <vector>

namespace lorgnette {

struct SurfaceBuffers {
  int width = 0, height = 0;
  std::vector<float> color_alpha;  // 4 per pixel, row-major, top row first: S_c.rgb (premultiplied), S_α
  std::vector<float> depth;        // 1 per pixel: S_t, +inf where nothing was hit
  std::vector<float> filter;       // 3 per pixel: F (1 where nothing tints); empty = 1 everywhere

  SurfaceBuffers() = default;
  SurfaceBuffers(int w, int h)
      : width(w),
        height(h),
        color_alpha(static_cast<size_t>(w) * h * 4, 0.0f),
        depth(static_cast<size_t>(w) * h, std::numeric_limits<float>::infinity()),
        filter(static_cast<size_t>(w) * h * 3, 1.0f) {}
  size_t pixel_count() const { return static_cast<size_t>(width) * height; }
};

}  // namespace lorgnette
