// The surface pass as hybrid-frame callbacks: see frame_surfaces.h.
#include "mesh/frame_surfaces.h"

#include <stdexcept>
#include <utility>

namespace lorgnette::mesh {

GlassesSurfaces frame_surfaces(std::shared_ptr<const SurfacePass> pass, const SurfaceParams& params) {
  if (!pass) throw std::invalid_argument("frame surfaces: no glasses surface pass was given (a null pass)");
  GlassesSurfaces g;
  g.screen_rect = [pass](const Camera& cam) {
    std::array<int, 4> r = pass->screen_rect(cam);
    return std::array<uint32_t, 4>{uint32_t(r[0]), uint32_t(r[1]), uint32_t(r[2]), uint32_t(r[3])};
  };
  g.render = [pass = std::move(pass), params](const Camera& cam, uint32_t spp) {
    SurfaceParams sp = params;
    sp.samples_per_pixel = int(spp);
    return pass->render(cam, sp);
  };
  return g;
}

}  // namespace lorgnette::mesh
