// Internal to the dataset loader: reading a frame's image (size only, or pixels as linear RGBA),
// and downscaling it by area averaging with premultiplied alpha so transparent pixels do not bleed
// their (meaningless) colour into the edges of the object.
#pragma once
#include <string>

#include "host/util/image_io.h"

namespace lorgnette::dataset::detail {

struct ImageHeader {
  int width = 0, height = 0, channels = 0;
  bool has_alpha = false;
};

// Reads only the header; throws naming the file when it is missing, unreadable or not an image.
ImageHeader read_image_header(const std::string& path);

// Reads the image as 4-channel linear RGBA (grey -> RGB, alpha = 1 when the file has none).
Image read_rgba(const std::string& path, bool* had_alpha);

// Reads a matte (nerfstudio's per-frame mask_path): the first channel of any image file as coverage
// in [0, 1] (1 channel, width x height; 0 = background). 8-bit masks map v / 255; masks written as
// 0/1 values (max 1/255) are read as binary. Throws naming the file when it is missing or corrupt.
Image read_mask(const std::string& path);

// Target size for an image of w x h under an integer factor and an optional max side (0 = none).
void scaled_size(int w, int h, int downscale, int max_side, int* out_w, int* out_h);

// Area-averaged resize of a 4-channel straight-alpha image to out_w x out_h.
Image resize_rgba(const Image& rgba, int out_w, int out_h);

}  // namespace lorgnette::dataset::detail
