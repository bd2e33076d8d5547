// The sizes printed on every frame (lens width, bridge, temple length) plus total width and lens
// height, measured on a canonical-mm mesh. Lens width and bridge come from the lens parts' extents
// (bridge = gap between the two lenses' inner edges); temple length is the arc length of the
// temple centreline from the hinge to the tip (approximate: +-10 mm against the printed value,
// since the hinge position is estimated as 12 mm behind the frame front).
#pragma once
#include <string>
#include <vector>

#include "mesh/refpoints.h"
#include "mesh/trimesh.h"

namespace lorgnette::mesh {

struct FrameMetrics {
  float total_width_mm = 0, total_height_mm = 0, total_depth_mm = 0;
  float lens_width_mm = 0, lens_height_mm = 0, bridge_mm = 0;  // 0 when the frame has no lens parts
  float temple_length_mm = 0;
  std::vector<int> lens_parts;  // parts mostly of lens material and at least 22 % of the width wide
};

FrameMetrics measure_frame(const TriMesh& canonical_mesh);

}  // namespace lorgnette::mesh
