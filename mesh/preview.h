// A preview sheet of a canonical glasses frame for `lorgnette glasses inspect -o`: front, left-side
// and top views rendered with the surface pass over a grey background, with g_c (red), g_l (green)
// and g_r (blue) marked and labelled, and the canonical axes named in each panel's caption.
#pragma once
#include "host/util/image_io.h"
#include "mesh/glasses.h"

namespace lorgnette::mesh {

struct PreviewOptions {
  int panel_width = 520, panel_height = 380;
  int samples_per_pixel = 4;
  int threads = 2;
};

// Linear RGB image, three panels side by side.
Image render_glasses_preview(const Glasses& glasses, const PreviewOptions& options = {});

}  // namespace lorgnette::mesh
