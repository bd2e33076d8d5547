// Structural checks of mesh files before Assimp reads them, for what Assimp 5.2 gets wrong
// (fuzz/regressions/glasses/). Its PLY reader loops forever on a header it cannot finish and
// allocates whatever an element or list count says: a 60-byte file asked for 17 GB. check_ply()
// reads the header (text lines, known keywords and types, end_header) and walks every record of
// every element, so that each count is covered by the bytes (binary) or numbers (ASCII) present.
// Its glTF reader trusts the GLB container's chunk lengths (a 21-byte file asked for 4 GB), and
// dereferences a null face for an indexed LINE_LOOP or TRIANGLE_FAN primitive with an index out of
// range; check_gltf() checks the container against the file's size and refuses those two modes.
#pragma once
#include <string>
#include <string_view>

namespace lorgnette::mesh {

// Throws std::runtime_error naming `name`, the header line or the element record, and what is
// wrong. Data after the last element is ignored, as readers do.
void check_ply(std::string_view bytes, const std::string& name);
// For a .gltf or .glb file's bytes: throws std::runtime_error naming `name` when a GLB header (magic
// "glTF", version 1 or 2, total length) or chunk does not fit the bytes, the first chunk is not JSON,
// or a mesh has an indexed LINE_LOOP (2) or TRIANGLE_FAN (6) primitive. JSON that does not parse is
// left to Assimp, which refuses it.
void check_gltf(std::string_view bytes, const std::string& name);

}  // namespace lorgnette::mesh
