// The sizes printed on every frame (lens width, bridge, temple length) plus total width and lens
// height, measured on a canonical-mm mesh. Lens width and bridge come from the lens parts' extents
// (bridge = gap between the two lenses' inner edges). Temple length is the industry's: from the
// hinge along the temple, the bend included, to the end of the tip (the third number printed on the
// temple). The hinge is where the temple leaves the back of the front (detect_temple_hinges, refined
// to the front's rearmost point there); the length is that of the temple's tracked centre line,
// averaged over both temples. Parametric frames (parametric.h) measure within 0.2 mm of the length
// they were made with; 0 when no temple is found. The hinges found on the way are kept for the fit's
// temple spread, so a frame's hinges are detected once per load.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "mesh/refpoints.h"
#include "mesh/temple_bend.h"
#include "mesh/trimesh.h"

namespace lorgnette::mesh {

struct FrameMetrics {
  float total_width_mm = 0, total_height_mm = 0, total_depth_mm = 0;
  float lens_width_mm = 0, lens_height_mm = 0, bridge_mm = 0;  // 0 when the frame has no lens parts
  float lens_centre_y_mm =
      0;  // the lenses' boxes' mean centre height (canonical y; the fit's lens-height advice)
  float temple_length_mm = 0;
  std::vector<int> lens_parts;         // parts mostly of lens material and at least 22 % of the width wide
  std::optional<TempleHinges> hinges;  // detect_temple_hinges (before the rearmost-point refinement)
  std::string no_hinges;               // why there are none
};

FrameMetrics measure_frame(const TriMesh& canonical_mesh);

}  // namespace lorgnette::mesh
