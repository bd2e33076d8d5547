// What the fit needs from a head representation, and nothing more: render a view for a camera,
// query density at points, and the scene's bounds plus an optional prior on where the face is.
// Implemented by the NeRF adapter (host/nerf + host/render) and by the mesh adapter (Embree ray
// casting of a textured head scan), so the fit's core never depends on either.
#pragma once
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "common/camera_types.h"
#include "host/util/image_io.h"

namespace lorgnette::fit {

struct Bounds {
  Eigen::Vector3f min{-1, -1, -1}, max{1, 1, 1};
  Eigen::Vector3f center() const { return 0.5f * (min + max); }
  Eigen::Vector3f size() const { return max - min; }
};

// Where the capture cameras were: the fit centres its first search there. Any field may be absent.
struct ViewPrior {
  Eigen::Vector3d up{0, 1, 0};            // world up (mean camera up for a capture)
  std::optional<Eigen::Vector3d> front;   // unit: from the head towards the typical camera
  std::optional<Eigen::Vector3d> target;  // a point on/inside the head the cameras look at
};

class ViewSource {
 public:
  virtual ~ViewSource() = default;
  // Linear RGB(A) image of the head for `cam` (width x height of the camera).
  virtual Image render(const Camera& cam) = 0;
  // Density at scene points (>= 0); for a mesh an inside indicator scaled to a large density.
  virtual std::vector<float> density(const std::vector<Eigen::Vector3f>& points) = 0;
  // Linear RGB at scene points seen along unit `dirs` (same size), for telling hair from skin
  // (hair.h); empty: this source has no colour there (the hair test is then off).
  virtual std::vector<Eigen::Vector3f> colour(const std::vector<Eigen::Vector3f>& points,
                                              const std::vector<Eigen::Vector3f>& dirs) {
    (void)points, (void)dirs;
    return {};
  }
  virtual Bounds bounds() const = 0;
  virtual ViewPrior prior() const { return {}; }
  // Density above which a point counts as inside the head (skin, for the contact and the surface
  // casts). A density is per scene unit, and scene units differ by 15x between captures (in2n-face
  // ~69 mm, fangzhou ~21 mm, the demo 200 mm): a NeRF source derives it from its marching step.
  virtual float surface_density() const { return 10.0f; }
  // True where the surface is exact (a mesh): its opacity steps from 0 to 1 at the skin, so a cast
  // never lands behind it. A volume (NeRF) may be soft where the capture saw it only at grazing
  // angles, which temple_depth.h corrects for; a hard surface needs no such correction.
  virtual bool hard_surface() const { return false; }
};

}  // namespace lorgnette::fit
