// A small rendered dataset of the procedural head for the capture tests (built once per binary):
// opaque grey background (no masks), 320x320 so the face spans ~130 px (dlib's detector needs ~80),
// one sample per pixel to keep the rendering to a couple of seconds. ctest runs each test in its own
// process, two at a time: the folder is per process so that they never write over each other.
#pragma once
#include <filesystem>
#include <string>

#include <unistd.h>

#include "host/dataset/dataset.h"
#include "synth/synthesize.h"
#include "tests/synth/test_head.h"

namespace lorgnette::capture::test {

inline const std::string& face_dataset_dir() {
  static const std::string dir = [] {
    std::filesystem::path d = std::filesystem::path(LORGNETTE_TEST_TMP) / "capture" /
                                ("synth_faces_" + std::to_string(::getpid()));
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d.parent_path());
    synth::SynthOptions o;
    o.views = 6;
    o.width = o.height = 320;
    o.samples_per_axis = 1;
    o.background = Eigen::Vector3f(0.5f, 0.5f, 0.5f);
    o.seed = 4;
    synth::synthesize_dataset(synth::test::default_head(), d.string(), o);
    return d.string();
  }();
  return dir;
}

}  // namespace lorgnette::capture::test
