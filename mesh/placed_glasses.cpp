// Load, spread the temples, build the surface pass (see placed_glasses.h).
#include "mesh/placed_glasses.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <fstream>
#include <stdexcept>

namespace lorgnette::mesh {

PlacedGlasses place_glasses_mesh(Glasses glasses, const Eigen::Matrix4d& transform,
                                 const TempleBend& temples) {
  PlacedGlasses p;
  p.temples = temples;
  p.transform = transform;
  if (temples.active()) {
    spdlog::info("glasses: temples spread {:.2f} deg (left) / {:.2f} deg (right) at the hinges",
                 temples.left.spread_deg, temples.right.spread_deg);
    bend_mesh(temples, glasses.mesh);
  }
  p.glasses = std::move(glasses);
  p.pass = std::make_unique<SurfacePass>(p.glasses.mesh, transform.cast<float>());
  return p;
}

PlacedGlasses load_placed_glasses(const std::string& glasses_path, const Eigen::Matrix4d& transform,
                                  const TempleBend& temples, const GlassesOptions& options) {
  return place_glasses_mesh(load_glasses(glasses_path, options), transform, temples);
}

}  // namespace lorgnette::mesh
