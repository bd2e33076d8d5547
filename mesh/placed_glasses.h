// The glasses as the renderer places them, in one call for every render path (`lorgnette render`,
// `lorgnette bench frames`, the demo): load and canonicalise the frame (load_glasses), spread its
// temples as the placement says (temple_bend.h), and build the surface pass for the placement
// transform (canonical mm -> scene). read_placement_temples() reads the spread from placement.json
// (a file without "temples" — written before they existed — means no spread).
#pragma once
#include <Eigen/Core>
#include <memory>
#include <string>

#include "mesh/glasses.h"
#include "mesh/surface_pass.h"
#include "mesh/temple_bend.h"

namespace lorgnette::mesh {

struct PlacedGlasses {
  Glasses glasses;     // mesh with the temples already spread
  TempleBend temples;  // what was applied
  // Canonical mm -> scene, in double as placement.json holds it; the surface pass (Embree) takes
  // it in float.
  Eigen::Matrix4d transform = Eigen::Matrix4d::Identity();
  std::unique_ptr<SurfacePass> pass;  // over the spread mesh
};

PlacedGlasses load_placed_glasses(const std::string& glasses_path, const Eigen::Matrix4d& transform,
                                  const TempleBend& temples = {}, const GlassesOptions& options = {});

// The same for a frame already in memory (canonical mm), e.g. a parametric one.
PlacedGlasses place_glasses_mesh(Glasses glasses, const Eigen::Matrix4d& transform,
                                 const TempleBend& temples);

}  // namespace lorgnette::mesh
