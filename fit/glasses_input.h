// The glasses as the fit needs them, from the mesh module: reference points g_c g_l g_r and surface
// samples of the frame (lenses excluded) in canonical millimetres, for the contact refinement, and the
// temple hinges (mesh/temple_bend.h) for the temple spread.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "fit/place.h"

namespace lorgnette::fit {

struct GlassesInput {
  std::string path;
  GlassesRefPoints ref;
  std::vector<Eigen::Vector3d> frame_points;  // canonical mm
  std::vector<std::string> notes;
};

// Loads and canonicalises a frame file (mesh::load_glasses); throws with the file's problem.
GlassesInput load_glasses_input(const std::string& path, int samples = 3000, unsigned seed = 1);

}  // namespace lorgnette::fit
