// Texture lookups on TriMesh textures: bilinear, repeat wrapping, uv in the glTF convention
// ((0, 0) = top-left texel corner, v grows downwards, as the loader stores them).
#pragma once
#include <Eigen/Core>

#include "host/util/image_io.h"

namespace lorgnette::mesh {

// Linear RGBA at uv (alpha = 1 for 1- or 3-channel images; grey images are replicated).
Eigen::Vector4f sample_texture(const Image& image, const Eigen::Vector2f& uv);

// Decodes an in-memory PNG/JPEG (embedded glTF texture) to a linear float image; colour channels
// are sRGB-decoded, alpha stays linear. Throws std::runtime_error when the bytes are not an image.
Image decode_image_bytes(const unsigned char* data, size_t size, const std::string& what);

// Halves the image until neither side exceeds max_side (box filter).
Image downsample_to(const Image& image, int max_side);

}  // namespace lorgnette::mesh
