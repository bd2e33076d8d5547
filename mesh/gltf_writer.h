// A small binary glTF 2.0 (.glb) writer for TriMesh (parametric frames, canonicalised exports):
// one node + mesh per part, one primitive per material used by the part, positions (in metres, as
// glTF requires: positions are multiplied by units_to_mm / 1000), normals when present, uint32
// indices, metallic-roughness materials, and KHR_materials_transmission / KHR_materials_ior for
// lenses. Textures are not written (parametric frames have none). The output reads back with
// load_mesh() part for part.
#pragma once
#include <string>

#include "mesh/trimesh.h"

namespace lorgnette::mesh {

// Throws std::runtime_error when the mesh is empty or the file cannot be written (atomic write).
void write_glb(const std::string& path, const TriMesh& mesh);

}  // namespace lorgnette::mesh
