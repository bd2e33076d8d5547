// The glasses as the fit needs them, from the mesh module: reference points g_c g_l g_r and surface
// samples of the frame (lenses excluded) in canonical millimetres, for the contact refinement, and the
// temple hinges (mesh/temple_bend.h) for the temple spread.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "fit/place.h"

namespace lorgnette::fit {

// The frame's sizes (mesh/frame_metrics.h) the fit advice compares with the head, canonical mm; 0 when
// not measurable (no lens parts, no temples found).
struct FrameSizes {
  double total_width_mm = 0, lens_width_mm = 0, lens_height_mm = 0, lens_centre_y_mm = 0, bridge_mm = 0;
  double temple_length_mm = 0;
};

struct GlassesInput {
  std::string path;
  GlassesRefPoints ref;
  FrameSizes sizes;
  std::vector<Eigen::Vector3d> frame_points;  // canonical mm
  std::vector<std::string> notes;
};

// Loads and canonicalises a frame file (mesh::load_glasses); throws with the file's problem.
GlassesInput load_glasses_input(const std::string& path, int samples = 3000, unsigned seed = 1);

}  // namespace lorgnette::fit
