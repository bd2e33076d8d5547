// Per-pixel sample positions for the surface pass: n jittered samples stratified over the pixel
// (a cols x rows grid with cols = round(sqrt n), one uniformly jittered sample in each of the first
// n cells), from a small deterministic per-pixel random stream (fixed seed => identical images).
#pragma once
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <vector>

namespace lorgnette::mesh {

// SplitMix64: tiny, well-distributed, seedable per pixel.
struct PixelRng {
  uint64_t state;
  explicit PixelRng(uint64_t seed) : state(seed) {}
  uint64_t next() {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  float uniform() { return static_cast<float>(next() >> 40) * (1.0f / 16777216.0f); }  // [0, 1)
};

inline uint64_t pixel_seed(uint64_t seed, int x, int y) {
  return seed * 0x100000001B3ull ^ (static_cast<uint64_t>(y) << 32 | static_cast<uint32_t>(x));
}

// Offsets in [0, 1)^2 inside the pixel.
inline void stratified_jitter(int n, PixelRng& rng, std::vector<Eigen::Vector2f>& out) {
  out.clear();
  if (n <= 1) {
    // One sample: jittered over the whole pixel (unbiased coverage), not fixed at the centre.
    out.emplace_back(rng.uniform(), rng.uniform());
    return;
  }
  int cols = std::max(1, static_cast<int>(std::lround(std::sqrt(static_cast<double>(n)))));
  int rows = (n + cols - 1) / cols;
  for (int k = 0; k < n; ++k) {
    int cx = k % cols, cy = k / cols;
    out.emplace_back((cx + rng.uniform()) / cols, (cy + rng.uniform()) / rows);
  }
}

}  // namespace lorgnette::mesh
