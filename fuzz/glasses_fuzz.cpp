// Fuzz target: the glasses loader front end, Assimp import from memory into a TriMesh (materials,
// embedded textures, node transforms; mesh/loader.h). The first byte picks the format (byte % 4:
// glb, gltf, obj, ply); the rest is the file. Canonicalisation (mesh/glasses.h) is left out: it
// samples 10^5 surface points whatever the mesh, ~0.3 s per input under the sanitizers.
#include <spdlog/spdlog.h>

#include <cstdint>
#include <exception>

#include "mesh/loader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace lorgnette::mesh;
  static const bool quiet = [] {  // the loader's warnings would flood the fuzzer's output
    spdlog::set_level(spdlog::level::off);
    return true;
  }();
  (void)quiet;
  if (size < 1) return 0;
  static const char* const kFormats[] = {"glb", "gltf", "obj", "ply"};
  LoadOptions options;
  options.max_texture_size = 64;
  LoadReport report;
  try {
    load_mesh_from_memory(data + 1, size - 1, kFormats[data[0] % 4], options, &report);
  } catch (const std::exception&) {
  }
  return 0;
}
