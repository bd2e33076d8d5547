// The compositing marcher's host side: drives the wavefront kernels of kernels/march/march.cl over
// tiles of pixels for any RadianceSource (the NeRF field or an analytic field), composites the
// glasses' surface buffers per paper Eq. 7 (premultiplied S_c; see kernels/march/march_math.h) and
// returns colour, expected depth and per-pixel sample counts.
#pragma once
#include <array>
#include <cstdint>
#include <memory>

#include "host/cl/kernel.h"
#include "host/render/fused_marcher.h"
#include "host/render/radiance_source.h"
#include "host/util/image_io.h"
#include "host/util/surface_buffers.h"
#include "kernels/march/march_types.h"

namespace lorgnette::render {

// Occupancy grid of the volume; layout LGN_MARCH_OCC_NONE marches every cell.
struct OccupancyGrid {
  uint32_t layout = LGN_MARCH_OCC_NONE;
  uint32_t resolution = 0;
  const cl::Buffer<uint32_t>* bits = nullptr;  // layout-specific words; not owned
};

// What is marched: the crop box (the head's AABB, scene units), the base step and the field.
struct VolumeScene {
  std::array<float, 3> aabb_min{0, 0, 0}, aabb_max{1, 1, 1};
  float step = 1.0f / 256.0f;  // scene units along the unit ray
  OccupancyGrid occupancy;
  RadianceSource* field = nullptr;
};

struct RenderOptions {
  uint32_t spp = 1;                  // rays per pixel (fixed sub-pixel pattern, averaged)
  float step_scale = 1.0f;           // multiplies the scene's step (>1 = faster, coarser)
  uint32_t max_samples_per_ray = 0;  // safety cap on segments per ray; 0: the box diagonal in steps + 8
  std::array<float, 3> background{1.0f, 1.0f, 1.0f};  // linear RGB behind the head
  bool alpha = false;                       // true: no background; rgb premultiplied by alpha = 1 - T
  float min_transmittance = 1e-4f;          // early termination threshold
  MarcherKind marcher = MarcherKind::Auto;  // wavefront or fused kernels (fused_marcher.h)
};

struct RenderResult {
  Image rgba;                      // 4 channels, linear; alpha = 1 - T (coverage of head + glasses)
  Image depth;                     // 1 channel: expected termination depth along the unit ray (0 where empty)
  Image samples;                   // 1 channel: NeRF segments composited per pixel (summed over spp)
  uint64_t samples_evaluated = 0;  // field evaluations issued (includes those past termination)
  uint64_t samples_composited = 0;  // sum of `samples`
  uint64_t rays = 0;
  uint32_t waves = 0;
  double seconds = 0.0;
  double samples_per_ray() const { return rays ? double(samples_composited) / double(rays) : 0.0; }
};

class Marcher {
 public:
  explicit Marcher(cl::Runtime& rt);
  // surfaces: nullptr for the head alone; otherwise its size must match the camera's.
  // Throws std::invalid_argument on inconsistent inputs (names what and how to fix).
  RenderResult render(const VolumeScene& scene, const Camera& cam, const lorgnette::SurfaceBuffers* surfaces,
                      const RenderOptions& options);

 private:
  void ensure_workspace(uint32_t max_batch);
  void march_tile(const VolumeScene& scene, MarchParams p, RenderResult& result);
  bool pick_fused(const VolumeScene& scene, const RenderOptions& o);
  void march_tile_fused(MarchParams p, const VolumeScene& scene, RenderResult& result);
  uint32_t scan(uint32_t n, const cl::Buffer<uint32_t>& in, cl::Buffer<uint32_t>& out);

  cl::Runtime& rt_;
  cl::Kernel init_, step_, scan_blocks_, scan_top_, scan_apply_, compact_, gather_, composite_;
  uint32_t batch_ = 0, tile_rays_ = 0;
  cl::Buffer<MarchRay> rays_;
  cl::Buffer<uint32_t> live_, live_next_, counts_, offsets_, flags_, block_sums_, total_, occ_dummy_;
  cl::Buffer<cl_float2> seg_;
  cl::Buffer<float> pos_, dir_, sigma_, rgb_;
  cl::Buffer<float> surf_ca_, surf_depth_, surf_filter_, out_rgba_, out_depth_;
  cl::Buffer<uint32_t> out_samples_;
  std::unique_ptr<FusedMarcher> fused_;  // made on the first fused frame
  bool fused_on_ = false;                // this frame marches with fused_
};

// Sub-pixel offset of pass s (s = 0 is the pixel centre; then an R2 low-discrepancy sequence).
std::array<float, 2> subpixel_offset(uint32_t s);

}  // namespace lorgnette::render
