// A glasses surface pass as a hybrid frame runs it (host/util/glasses_surfaces.h): traced inside its
// screen rectangle at the frame's samples per pixel. The one adapter for every caller (the viewer,
// `lorgnette bench frames`, the march benchmark). The callbacks hold the pass by shared_ptr, so a
// frame rendering on another thread keeps it alive even if its owner lets it go meanwhile.
#pragma once
#include <memory>

#include "host/util/glasses_surfaces.h"
#include "mesh/surface_pass.h"

namespace lorgnette::mesh {

// `params` are the pass's settings apart from samples_per_pixel, which each frame chooses. Throws
// std::invalid_argument for a null pass.
GlassesSurfaces frame_surfaces(std::shared_ptr<const SurfacePass> pass, const SurfaceParams& params = {});

}  // namespace lorgnette::mesh
