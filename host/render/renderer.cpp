// NerfModel rendering through the compositing marcher: see renderer.h.
#include "host/render/renderer.h"

#include <spdlog/spdlog.h>

#include "host/dataset/dataset.h"

namespace lorgnette::render {

std::vector<Camera> capture_cameras(const nerf::NerfModel& model) {
  const std::string& path = model.metadata.dataset_path;
  if (path.empty()) return {};
  try {
    dataset::LoadOptions lo;
    lo.load_images = false;
    lo.any_missing_images_ok = true;
    auto ds = dataset::load_dataset(path, lo);
    std::vector<Camera> cams;
    for (const auto& f : ds.frames) cams.push_back(f.camera);
    spdlog::debug("orbit front from the capture's {} cameras", cams.size());
    return cams;
  } catch (const std::exception& e) {
    spdlog::warn("could not read the model's dataset '{}' ({}); using +z as the front", path, e.what());
    return {};
  }
}

VolumeScene model_scene(nerf::NerfModel& model, RadianceSource& source) {
  VolumeScene scene;
  scene.aabb_min = model.aabb().min;
  scene.aabb_max = model.aabb().max;
  scene.step = model.step();
  scene.occupancy = {LGN_MARCH_OCC_LINEAR, model.occupancy_resolution(), &model.occupancy_bits()};
  scene.field = &source;
  return scene;
}

RenderResult Renderer::render(nerf::NerfModel& model, const Camera& cam,
                              const lorgnette::SurfaceBuffers* surfaces, const RenderOptions& options) {
  NerfSource source(model.field());
  return marcher_.render(model_scene(model, source), cam, surfaces, options);
}

RenderResult Renderer::render_frame(nerf::NerfModel& model, const Camera& cam, const GlassesSurfaces* glasses,
                                    const FrameOptions& options) {
  NerfSource source(model.field());
  return render_hybrid_frame(marcher_, model_scene(model, source), cam, glasses, options);
}

RenderResult render(nerf::NerfModel& model, const Camera& cam, const lorgnette::SurfaceBuffers* surfaces,
                    const RenderOptions& options) {
  Renderer r(model.runtime());
  return r.render(model, cam, surfaces, options);
}

OrbitSpec model_orbit(const nerf::NerfModel& model, const std::vector<Camera>& capture_cameras) {
  OrbitSpec spec;
  const nerf::Aabb& box = model.aabb();
  spec.center = box.center();
  spec.half_extent = {0.5f * box.extent(0), 0.5f * box.extent(1), 0.5f * box.extent(2)};
  if (!capture_cameras.empty()) {
    spec.front = front_from_cameras(capture_cameras);
    spec.up = up_from_cameras(capture_cameras);
  }
  return spec;
}

}  // namespace lorgnette::render
