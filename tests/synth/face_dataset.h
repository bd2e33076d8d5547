// A small rendered dataset of the default procedural head for tests that need dlib to find a face:
// opaque grey background (no masks), 320x320 so the face spans ~130 px (dlib's detector needs ~80),
// one sample per pixel to keep the rendering to a few seconds. ctest runs each test in its own
// process, two at a time: the folder is per process so that they never write over each other.
#pragma once
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <string>

#include "synth/synthesize.h"
#include "tests/synth/test_head.h"

namespace lorgnette::synth::test {

// Renders `views` views (camera seed `seed`, before a plain `background`, linear RGB) into
// LORGNETTE_TEST_TMP/<area>/<name>_<pid>; returns it.
inline std::string render_face_dataset(const std::string& area, const std::string& name, int views,
                                       uint64_t seed,
                                       const Eigen::Vector3f& background = Eigen::Vector3f(0.5f, 0.5f,
                                                                                           0.5f)) {
  std::filesystem::path d =
      std::filesystem::path(LORGNETTE_TEST_TMP) / area / (name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d.parent_path());
  SynthOptions o;
  o.views = views;
  o.width = o.height = 320;
  o.samples_per_axis = 1;
  o.background = background;
  o.seed = seed;
  synthesize_dataset(default_head(), d.string(), o);
  return d.string();
}

}  // namespace lorgnette::synth::test
