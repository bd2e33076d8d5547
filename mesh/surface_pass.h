// The glasses surface pass (paper section 3.2, first rendering stage): for a Camera and a placement
// (canonical mm -> scene, scale included) it traces N jittered stratified samples per pixel with
// Embree and fills the SurfaceBuffers the compositing marcher reads:
// - S_c: premultiplied linear RGB, the mean over samples of the light the frame sends to the camera;
// - S_α: the mean over samples of (1 - transmittance to what lies behind): a miss adds 0, an opaque
//   hit 1, a lens 1 - T with T = (1 - F) * transmission * tint (mean over RGB), so the eyes stay
//   visible; alpha-blended materials pass (1 - alpha);
// - F: the tint of what passes, per channel: the mean transmittance per channel over samples divided
//   by its mean over channels (1 - S_α), so a green lens shows the eyes behind it green;
// - S_t: the NEAREST first-hit distance over the pixel's samples (along the unit primary ray, scene
//   units; +inf when no sample hits). Nearest rather than a coverage-weighted mean so that the
//   marcher never composites NeRF density that lies in front of any visible part of the frame.
// Shading: the simplified Disney BRDF (disney_brdf.h) under Lighting (hemisphere + key light with a
// soft shadow ray); lenses reflect with dielectric Fresnel and transmit tinted light, and rays go on
// through up to `max_layers` transmissive surfaces. Rows run in parallel on `threads` threads;
// pixels outside the frame's projected bounding box (screen_rect) are skipped: no ray can hit there,
// so their buffers keep S_α = 0, S_t = +inf, F = 1, as a traced miss would leave them.
#pragma once
#include <Eigen/Core>
#include <array>
#include <memory>

#include "common/camera_types.h"
#include "host/util/surface_buffers.h"
#include "mesh/embree_scene.h"
#include "mesh/lighting.h"
#include "mesh/trimesh.h"

namespace lorgnette::mesh {

struct SurfaceParams {
  int samples_per_pixel = 4;
  uint64_t seed = 1;
  int threads = 2;
  int max_layers = 6;
  Lighting lighting;
  float min_lens_tint = 0.15f;  // dark sunglass tints are floored so the eyes stay visible
  bool clip_to_bounds = true;   // false: trace every pixel (the reference for the clipped pass)
};

class SurfacePass {
 public:
  // `canonical_mesh` in millimetres (canonical frame); `placement` maps it into the scene.
  SurfacePass(const TriMesh& canonical_mesh, const Eigen::Matrix4f& placement);
  SurfaceBuffers render(const Camera& camera, const SurfaceParams& params) const;
  // Pixel rectangle {x0, y0, x1, y1} (half-open) outside which no primary ray hits the frame: its
  // placed bounding box projected (a 5x5x5 grid of points, so mild lens distortion is covered) plus
  // a 2-pixel margin; the whole image when any of those points lies behind the camera.
  std::array<int, 4> screen_rect(const Camera& camera) const;
  const EmbreeScene& scene() const { return *scene_; }

 private:
  std::unique_ptr<EmbreeScene> scene_;
  Eigen::Matrix3f scene_to_canonical_rot_;  // rotation only: for lighting directions
};

// Camera looking from `eye` at `target` (OpenGL convention), ideal pinhole, vertical field of view.
Camera look_at_camera(const Eigen::Vector3f& eye, const Eigen::Vector3f& target, const Eigen::Vector3f& up,
                      float fov_y_deg, int width, int height);

}  // namespace lorgnette::mesh
