// True mattes of synthetic captures, for evaluation only: 8-bit grey PNGs whose value is the
// subject's coverage of the pixel (0 = room, 255 = subject), not sRGB-encoded colour. Datasets
// reference them from transforms.json frames as "eval_matte_path", a key training never reads.
#pragma once
#include <string>

#include "host/util/image_io.h"

namespace lorgnette::synth {

// matte: 1 channel, coverage in [0, 1].
void write_matte(const std::string& path, const Image& matte);
// 1 channel, coverage in [0, 1]. Throws std::runtime_error naming the file when unreadable.
Image read_matte(const std::string& path);

}  // namespace lorgnette::synth
