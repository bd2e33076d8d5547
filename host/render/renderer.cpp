// NerfModel rendering through the compositing marcher: see renderer.h.
#include "host/render/renderer.h"

namespace lorgnette::render {

RenderResult Renderer::render(nerf::NerfModel& model, const Camera& cam, const mesh::SurfaceBuffers* surfaces,
                              const RenderOptions& options) {
  NerfSource source(model.field());
  VolumeScene scene;
  scene.aabb_min = model.aabb().min;
  scene.aabb_max = model.aabb().max;
  scene.step = model.step();
  scene.occupancy = {LGN_MARCH_OCC_LINEAR, model.occupancy_resolution(), &model.occupancy_bits()};
  scene.field = &source;
  return marcher_.render(scene, cam, surfaces, options);
}

RenderResult render(nerf::NerfModel& model, const Camera& cam, const mesh::SurfaceBuffers* surfaces,
                    const RenderOptions& options) {
  Renderer r(model.runtime());
  return r.render(model, cam, surfaces, options);
}

}  // namespace lorgnette::render
