// Loading triangle meshes from the files shops and scanners produce — glTF 2.0 (.gltf + .bin, .glb),
// OBJ (+MTL) and PLY — through Assimp into a TriMesh. Node transforms are baked into the vertices
// (each mesh instance of the node hierarchy becomes one named part), materials keep the glTF
// metallic-roughness parameters, alpha, KHR_materials_transmission / ior / volume where Assimp
// exposes them, and base-colour textures (external files or embedded in a .glb) are decoded to
// linear float images. Positions stay in the file's units (units_to_mm records the file's unit
// when the format states one: glTF is metres); glasses are canonicalised afterwards (canonical.h).
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "mesh/trimesh.h"

namespace lorgnette::mesh {

// How texture v is read. TriMesh::uvs use the glTF convention ((0, 0) = top-left texel), which
// Assimp delivers for every format (its glTF importer flips to OpenGL and aiProcess_FlipUVs flips
// back). Some files break their format's rule: kAuto flips v only for glTF files whose generator is
// known to copy OpenGL-convention UVs unchanged (uv_flip_for_generator); kYes / kNo force it.
enum class FlipV { kAuto, kNo, kYes };

// True for glTF generators known to store OpenGL-convention UVs (e.g. "probe js2glb.py", which
// repacked three.js's Lee Perry-Smith head without flipping v).
bool uv_flip_for_generator(const std::string& generator);

struct LoadOptions {
  FlipV flip_v = FlipV::kAuto;
  bool load_textures = true;     // decode base-colour textures (off: faster, geometry only)
  bool generate_normals = true;  // smooth normals when the file has none
  int max_texture_size = 4096;   // larger textures are downsampled (memory: 16 bytes per texel)
};

struct LoadReport {
  std::vector<std::string> warnings;  // missing textures, degenerate triangles dropped, ...
  int degenerate_triangles = 0;       // zero-area triangles removed
};

// Throws std::runtime_error with the path, what is wrong and what to do for missing, unreadable,
// corrupt or empty files (no triangles). Never returns an empty mesh.
TriMesh load_mesh(const std::string& path, const LoadOptions& options = {}, LoadReport* report = nullptr);
// The same from a file's bytes; `format` is its extension: gltf, glb, obj or ply. Nothing outside
// the bytes is read (a .gltf's external buffers, an .obj's .mtl, external textures are missing).
TriMesh load_mesh_from_memory(const void* data, size_t bytes, const std::string& format,
                              const LoadOptions& options = {}, LoadReport* report = nullptr);

// Heuristic lens test on a material (transmission, translucent blend, or a glass-like name);
// the loader sets Material::is_lens with it.
bool looks_like_lens(const Material& m, const std::string& alpha_mode);

}  // namespace lorgnette::mesh
