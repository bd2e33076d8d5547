// The ViewSource over a trained NeRF (host/nerf NerfModel, rendered with host/render's marcher):
// views composited over white, density = the field's sigma at AABB-normalised points (0 outside
// the box and in the occupancy grid's empty cells, where the marcher never samples: a room-model
// training leaves only the subject's connected region occupied, so the fit probes the subject's
// density, never the room's), colour = the field's RGB there, and a prior from the capture's
// cameras (mean up, mean direction towards the cameras) read from the model's dataset when it is
// still there.
#pragma once
#include <memory>
#include <string>

#include "fit/view_source.h"
#include "host/nerf/model.h"
#include "host/render/renderer.h"

namespace lorgnette::fit {

class NerfViewSource : public ViewSource {
 public:
  // The renderer's defaults, including its 1e-4 transmittance cut-off: 1/255 (the views only feed
  // an 8-bit detector) renders 15-20 % faster but moves the scan's ears by up to 2 mm, past the
  // 4 mm target on two of three models.
  NerfViewSource(nerf::NerfModel& model, ViewPrior prior, render::RenderOptions options = {});
  Image render(const Camera& cam) override;
  std::vector<float> density(const std::vector<Eigen::Vector3f>& points) override;
  std::vector<Eigen::Vector3f> colour(const std::vector<Eigen::Vector3f>& points,
                                      const std::vector<Eigen::Vector3f>& dirs) override;
  Bounds bounds() const override;
  ViewPrior prior() const override { return prior_; }
  // kSurfaceOpticalDepth per marching step: the models size their step to 1.1-1.3 mm whatever the scene
  // unit, so this is the same physical threshold everywhere (10 per unit on the 324 mm/unit scan).
  float surface_density() const override;
  static constexpr float kSurfaceOpticalDepth = 0.04f;

 private:
  nerf::NerfModel& model_;
  ViewPrior prior_;
  render::RenderOptions options_;
  render::Renderer renderer_;
  // Normalised positions of `points` from `start` (at most a batch) into pos_ (SoA, clamped);
  // returns which lie inside the box in an occupied cell.
  std::vector<bool> upload_positions(const std::vector<Eigen::Vector3f>& points, size_t start, uint32_t n);

  cl::Buffer<float> pos_, sigma_, dir_, rgb_;
};

// Mean camera up and the direction from the AABB centre to the mean camera position, from an
// instant-ngp / nerfstudio transforms.json (mapped into the model frame with its normalisation);
// {} when the file is missing or has no frames.
ViewPrior prior_from_transforms(const std::string& transforms_json, const nerf::NerfModel& model);

}  // namespace lorgnette::fit
