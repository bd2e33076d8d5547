// The compositing marcher's host side: drives the wavefront kernels of kernels/march/march.cl over
// tiles of pixels for any RadianceSource (the NeRF field or an analytic field), composites the
// glasses' surface buffers per paper Eq. 7 (premultiplied S_c; see kernels/march/march_math.h) and
// returns colour, expected depth and per-pixel sample counts.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
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
  bool alpha = false;               // true: no background; rgb premultiplied by alpha = 1 - T
  float min_transmittance = 1e-4f;  // early termination threshold
  // Segments each live ray emits per wave: wave_min while the tile is full, up to wave_max as rays
  // finish. Small waves evaluate fewer samples past early termination; every wave costs its kernel
  // launches and two read-backs (docs/bench/frames.md measures the trade). The image does not depend
  // on them.
  uint32_t wave_min = 2, wave_max = 8;
  MarcherKind marcher = MarcherKind::Auto;  // wavefront or fused kernels (fused_marcher.h)
};

// Where the frame's time went (seconds). The march's kernels run while the host waits on its
// read-backs, so `march` is the device's marching time as the host sees it.
struct FrameTimes {
  double march = 0.0;         // marching the frame, less the lines below
  double upload = 0.0;        // surface buffers to the device
  double readback = 0.0;      // colour, depth and counts back to the host
  double surface_wait = 0.0;  // the march idle, waiting for the surface pass to finish
  double surface = 0.0;       // the surface pass itself (on its own thread when concurrent); 0 without
};

struct RenderResult {
  Image rgba;                      // 4 channels, linear; alpha = 1 - T (coverage of head + glasses)
  Image depth;                     // 1 channel: expected termination depth along the unit ray (0 where empty)
  Image samples;                   // 1 channel: NeRF segments composited per pixel (summed over spp)
  uint64_t samples_evaluated = 0;  // field evaluations issued (includes those past termination)
  uint64_t samples_composited = 0;  // sum of `samples`
  uint64_t rays = 0;
  uint32_t waves = 0;
  bool fused = false;    // marched by the fused kernel (fused_marcher.h), else by the wavefront one
  double seconds = 0.0;  // the whole frame as the caller waited for it
  FrameTimes times;
  double samples_per_ray() const { return rays ? double(samples_composited) / double(rays) : 0.0; }
};

// Surface buffers still being computed (the surface pass on another thread) when the march starts.
// Rows outside [row_begin, row_end) have no surface (S_α = 0 there): they are marched first. `wait`
// blocks until the buffers are complete and returns them; it is called once, only when the band is
// not empty. An empty `wait` means no surface at all.
struct PendingSurfaces {
  uint32_t row_begin = 0, row_end = 0;
  std::function<const lorgnette::SurfaceBuffers&()> wait;
};

class Marcher {
 public:
  explicit Marcher(cl::Runtime& rt);
  // surfaces: nullptr for the head alone; otherwise its size must match the camera's.
  // Throws std::invalid_argument on inconsistent inputs (names what and how to fix).
  RenderResult render(const VolumeScene& scene, const Camera& cam, const lorgnette::SurfaceBuffers* surfaces,
                      const RenderOptions& options);
  // The same frame with the surface still to come: the rows without a surface are marched while it
  // is computed, the band after `surfaces.wait()`. The image equals the one above bit for bit.
  RenderResult render(const VolumeScene& scene, const Camera& cam, const PendingSurfaces& surfaces,
                      const RenderOptions& options);

 private:
  void ensure_workspace(uint32_t max_batch, uint32_t wave_min);
  void march_pixels(const VolumeScene& scene, MarchParams p, uint32_t begin, uint32_t end, uint32_t spp,
                    const RenderOptions& o, RenderResult& result);
  void march_tile(const VolumeScene& scene, MarchParams p, const RenderOptions& o, RenderResult& result);
  bool pick_fused(const VolumeScene& scene, const RenderOptions& o);
  void march_tile_fused(MarchParams p, const VolumeScene& scene, RenderResult& result);
  void upload_surfaces(const lorgnette::SurfaceBuffers& s, uint32_t begin, uint32_t end);
  void clear_outputs(uint32_t pixels);
  void read_back(const Camera& cam, uint32_t spp, RenderResult& result);
  uint32_t scan(uint32_t n, const cl::Buffer<uint32_t>& in, cl::Buffer<uint32_t>& out);

  cl::Runtime& rt_;
  cl::Kernel init_, step_, scan_blocks_, scan_top_, scan_apply_, compact_, gather_, composite_;
  uint32_t batch_ = 0, wave_min_ = 0, tile_rays_ = 0;
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
