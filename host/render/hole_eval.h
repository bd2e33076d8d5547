// Holes in a render of a subject, judged against its true matte (synth --room captures): the head's
// interior is the matte (>= 0.5) eroded by 7 px, in the upper 45 % of the subject's rows (the head
// above the shoulders), and a hole is a pixel of it the render leaves transparent (opacity < 0.5).
// A pale face before a pale wall loses pixels there to the room model (#41); the matte's edge, where
// any separation is soft, and the body below the head are not judged.
#pragma once
#include <cstdint>
#include <vector>

#include "host/util/image_io.h"

namespace lorgnette::render {

struct HoleEvalOptions {
  int erode_px = 7;            // the matte's edge left out
  double upper_share = 0.45;   // of the subject's rows, from its top
  float opacity_below = 0.5f;  // transparent
};

struct InteriorHoles {
  double share = 0.0;  // holes / interior pixels (0 when there is no interior)
  long interior_pixels = 0, holes = 0;
};

// The head's interior of `matte` (1-channel coverage): 1 per judged pixel, row-major, width x height.
std::vector<uint8_t> head_interior_mask(const Image& matte, const HoleEvalOptions& options = {});

// `prediction`: RGBA (alpha = opacity); `matte`: 1-channel coverage of the same size.
InteriorHoles head_interior_holes(const Image& prediction, const Image& matte,
                                  const HoleEvalOptions& options = {});

}  // namespace lorgnette::render
