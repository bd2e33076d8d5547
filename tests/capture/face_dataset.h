// The capture tests' rendered face dataset (tests/synth/face_dataset.h), built once per binary.
#pragma once
#include <string>

#include "tests/synth/face_dataset.h"

namespace lorgnette::capture::test {

inline const std::string& face_dataset_dir() {
  static const std::string dir = synth::test::render_face_dataset("capture", "synth_faces", 6, 4);
  return dir;
}

}  // namespace lorgnette::capture::test
