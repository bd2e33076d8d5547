// A structural check of PLY files before Assimp reads them. Assimp 5.2's PLY reader loops forever
// on a header it cannot finish, and allocates whatever an element or list count says: a 60-byte
// file can ask for 17 GB (fuzz/regressions/glasses/). check_ply() reads the header (text lines,
// known keywords and types, end_header) and walks every record of every element, so that each count
// is covered by the bytes (binary) or numbers (ASCII) actually present.
#pragma once
#include <string>
#include <string_view>

namespace lorgnette::mesh {

// Throws std::runtime_error naming `name`, the header line or the element record, and what is
// wrong. Data after the last element is ignored, as readers do.
void check_ply(std::string_view bytes, const std::string& name);

}  // namespace lorgnette::mesh
