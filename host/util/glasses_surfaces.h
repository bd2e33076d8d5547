// The glasses' surface pass as one hybrid frame calls it (host/render/hybrid_frame.h): two callbacks,
// the screen rectangle the glasses can cover and the surface buffers for a camera. The contract
// between mesh/ (which provides them, mesh/frame_surfaces.h) and host/render (which calls them), so it
// lives on the ground floor beside SurfaceBuffers and neither module includes the other.
#pragma once
#include <array>
#include <cstdint>
#include <functional>

#include "common/camera_types.h"
#include "host/util/surface_buffers.h"

namespace lorgnette {

struct GlassesSurfaces {
  // Pixel rectangle {x0, y0, x1, y1} (half-open) outside which no primary ray can hit the glasses;
  // the whole image when that cannot be told (a corner of their box behind the camera).
  std::function<std::array<uint32_t, 4>(const Camera&)> screen_rect;
  // The surface pass at `spp` samples per pixel, tracing only inside screen_rect (S_α = 0 elsewhere).
  std::function<SurfaceBuffers(const Camera&, uint32_t spp)> render;
};

}  // namespace lorgnette
