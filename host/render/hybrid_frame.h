// One hybrid frame (paper section 3.2): the glasses' surface pass and the NeRF march of the same
// camera. Concurrently by default: the surface pass runs on a host thread (Embree on the CPU) while
// the device marches the rows the glasses cannot reach; the band of rows inside the glasses'
// projected screen bounds is marched once the surface buffers are ready, so the composite of
// Eq. 7 sees them. Sequential mode (surface pass, then march) is the reference the concurrent frame
// must equal bit for bit. The surface pass comes in as callbacks, so this library does not depend
// on the mesh module.
#pragma once
#include <cstdint>

#include "host/render/marcher.h"
#include "host/util/glasses_surfaces.h"
#include "host/util/surface_buffers.h"

namespace lorgnette::render {

// The glasses as one frame needs them (mesh/frame_surfaces.h makes them from a surface pass).
using GlassesSurfaces = lorgnette::GlassesSurfaces;

struct FrameOptions {
  RenderOptions march;
  uint32_t surface_spp = 4;  // glasses samples per pixel (an interactive view uses 1 while moving)
  bool concurrent = true;    // false: the surface pass first, then the march
};

// glasses: nullptr for the head alone. result.times.surface is the surface pass's own time (on its
// thread when concurrent); result.seconds the whole frame. Exceptions of either side propagate.
RenderResult render_hybrid_frame(Marcher& marcher, const VolumeScene& scene, const Camera& cam,
                                 const GlassesSurfaces* glasses, const FrameOptions& options);

}  // namespace lorgnette::render
