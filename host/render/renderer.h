// Rendering a trained NeRF head (host/nerf NerfModel), optionally with the glasses' surface
// buffers, through the compositing marcher: the model's field is the radiance source, its AABB the
// crop box (the background is pruned, as the paper does), its occupancy grid and step drive the
// march.
#pragma once
#include "host/nerf/model.h"
#include "host/render/hybrid_frame.h"
#include "host/render/marcher.h"
#include "host/render/orbit.h"

namespace lorgnette::render {

// The NeRF field as a radiance source (inference forward, no backward state kept).
class NerfSource : public RadianceSource {
 public:
  explicit NerfSource(field::Field& field) : field_(field) {}
  uint32_t max_batch() const override { return field_.max_batch(); }
  void evaluate(const cl::Buffer<float>& pos, const cl::Buffer<float>& dir, uint32_t n,
                cl::Buffer<float>& sigma, cl::Buffer<float>& rgb) override {
    field_.forward(pos, dir, n, sigma, rgb, false);
  }
  InKernelField in_kernel() override { return {nullptr, &field_}; }

 private:
  field::Field& field_;
};

class Renderer {
 public:
  explicit Renderer(cl::Runtime& rt) : marcher_(rt) {}
  // surfaces: nullptr for the head alone. Throws std::invalid_argument on inconsistent inputs.
  RenderResult render(nerf::NerfModel& model, const Camera& cam, const lorgnette::SurfaceBuffers* surfaces,
                      const RenderOptions& options);
  // The head with the glasses' surface pass run for the same camera, overlapped with the march
  // (hybrid_frame.h); glasses: nullptr for the head alone.
  RenderResult render_frame(nerf::NerfModel& model, const Camera& cam, const GlassesSurfaces* glasses,
                            const FrameOptions& options);

 private:
  Marcher marcher_;
};

// The model as the marcher's scene: its box, step, occupancy grid, and `source` (its field).
VolumeScene model_scene(nerf::NerfModel& model, RadianceSource& source);

// One-shot convenience (builds the marcher; kernels come from the runtime's cache).
RenderResult render(nerf::NerfModel& model, const Camera& cam, const lorgnette::SurfaceBuffers* surfaces,
                    const RenderOptions& options);

// The cameras of the dataset the model was trained on (as its snapshot names it), in the dataset's
// own frame, without images; {} with a warning when the model names none or it cannot be read.
// They mark the face's front for orbits and the range of directions the capture saw.
std::vector<Camera> capture_cameras(const nerf::NerfModel& model);

// An orbit framing the model's box; its front and up come from the capture's cameras (the face's
// front) when given, else +z and +y. Views, elevation, field of view and size keep their defaults.
OrbitSpec model_orbit(const nerf::NerfModel& model, const std::vector<Camera>& capture_cameras);

}  // namespace lorgnette::render
