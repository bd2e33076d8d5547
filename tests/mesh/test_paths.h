// Paths of the shared test models (read in place from LORGNETTE_DATA_DIR, never copied).
#pragma once
#include <string>
#include <vector>

namespace lorgnette::mesh::test {

inline std::string data(const std::string& rel) { return std::string(LORGNETTE_DATA_DIR) + "/" + rel; }

struct SharedGlasses {
  const char* name;
  const char* path;  // relative to the data dir
};

inline const std::vector<SharedGlasses>& shared_glasses() {
  static const std::vector<SharedGlasses> all = {
      {"glasses-01", "glasses/glasses-01/scene.gltf"},
      {"glasses-03", "glasses/glasses-03/scene.gltf"},
      {"glasses-04", "glasses/glasses-04/scene.gltf"},
      {"glasses-05", "glasses/glasses-05/scene.gltf"},
      {"glasses-06", "glasses/glasses-06/scene.gltf"},
      {"glasses-07", "glasses/glasses-07/scene.gltf"},
      {"khronos", "glasses/khronos-sunglasses/SunglassesKhronos.glb"}};
  return all;
}

}  // namespace lorgnette::mesh::test
