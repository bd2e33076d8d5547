// The glasses as the renderer places them, in one call for every render path (`lorgnette render`,
// `lorgnette bench frames`, the demo): load and canonicalise the frame (load_glasses), spread its
// temples as the placement says (temple_bend.h), and build the surface pass for the placement
// transform (canonical mm -> scene). read_placement_temples() reads the spread from placement.json
// (a file without "temples" — written before they existed — means no spread).
#pragma once
#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>

#include "mesh/glasses.h"
#include "mesh/surface_pass.h"
#include "mesh/temple_bend.h"

namespace lorgnette::mesh {

struct PlacedGlasses {
  Glasses glasses;                                          // mesh with the temples already spread
  TempleBend temples;                                       // what was applied
  Eigen::Matrix4f transform = Eigen::Matrix4f::Identity();  // canonical mm -> scene
  std::unique_ptr<SurfacePass> pass;                        // over the spread mesh
};

PlacedGlasses load_placed_glasses(const std::string& glasses_path, const Eigen::Matrix4f& transform,
                                  const TempleBend& temples = {}, const GlassesOptions& options = {});

// A row-major 4x4 (as the render library's Mat4 and placement.json hold it) as an Eigen matrix.
inline Eigen::Matrix4f row_major_matrix(const std::array<float, 16>& m) {
  Eigen::Matrix4f out;
  for (int i = 0; i < 16; ++i) out(i / 4, i % 4) = m[i];
  return out;
}

// The same for a frame already in memory (canonical mm), e.g. a parametric one.
PlacedGlasses place_glasses_mesh(Glasses glasses, const Eigen::Matrix4f& transform,
                                 const TempleBend& temples);

}  // namespace lorgnette::mesh
