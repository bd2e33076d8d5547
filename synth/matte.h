// True mattes of synthetic captures, for evaluation only: 8-bit grey PNGs whose value is the
// subject's coverage of the pixel (0 = room, 255 = subject), not sRGB-encoded colour. Datasets
// reference them from transforms.json frames as "eval_matte_path", a key training never reads.
#pragma once
#include <map>
#include <string>

#include "host/util/image_io.h"

namespace lorgnette::synth {

// matte: 1 channel, coverage in [0, 1].
void write_matte(const std::string& path, const Image& matte);
// 1 channel, coverage in [0, 1]. Throws std::runtime_error naming the file when unreadable.
Image read_matte(const std::string& path);

// A synthetic capture's evaluation files for one frame, relative to the dataset folder: its true
// matte ("eval_matte_path") and subject depth ("depth_path"; "" when the frame names none).
struct EvalFiles {
  std::string matte, depth;
};
// The evaluation files of `dataset_dir`'s frames that have a true matte, by image file stem. Empty
// when the folder has no readable transforms.json or no frame names a matte.
std::map<std::string, EvalFiles> eval_files_by_stem(const std::string& dataset_dir);

}  // namespace lorgnette::synth
