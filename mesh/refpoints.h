// The glasses' reference points (paper section 3.1): g_c on the nose bridge and g_l, g_r on the
// temples where they rest on the ears. Detected automatically on a canonicalised frame, or read
// from a sidecar `<file>.refpoints.json` that overrides detection.
//
// Definitions (used identically by detection and by parametric frames):
// - g_c: on the symmetry plane (x = 0), the underside of the bridge at the back face of the frame
//   front — where the bridge rests on the top of the nose.
// - g_l (x > 0, the wearer's left) / g_r: on the temple underside where the ear carries it: the
//   "knee" where the temple bends down behind the ear (the underside point farthest above the chord
//   from the temple's front to its tip); on a straight temple, the underside at 75 % of its depth.
// Detected points are made exactly mirror-symmetric (the two detections are averaged).
//
// Sidecar JSON: {"version": 1, "space": "file", "g_c": [x,y,z], "g_l": [...], "g_r": [...],
// "mm_per_unit": optional}. Coordinates are the mesh file's own (after its node transforms, in its
// units) — what a 3D tool shows — and go through the same canonicalisation as the mesh.
#pragma once
#include <Eigen/Core>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mesh/trimesh.h"

namespace lorgnette::mesh {

struct RefPoints {
  Eigen::Vector3f g_c{0, 0, 0}, g_l{0, 0, 0}, g_r{0, 0, 0};
  std::string source;              // "detected", "sidecar" or "parametric"
  std::vector<std::string> notes;  // what detection found or had to assume
};

// Per-triangle flag: true where the triangle's material is a lens.
std::vector<bool> lens_triangles(const TriMesh& mesh);

// Detects the points on a canonical-mm mesh (x symmetric about 0, +y up, +z forward).
// Throws std::runtime_error when the mesh has no temples/bridge to detect (e.g. not a frame).
RefPoints detect_refpoints(const TriMesh& canonical_mesh);

struct RefPointsSidecar {
  RefPoints points;
  std::string space = "file";  // the only space so far: the mesh file's coordinates
  double mm_per_unit = 0.0;    // > 0 overrides unit detection
};

std::string sidecar_path(const std::string& mesh_path);  // mesh_path + ".refpoints.json"
// Reads the sidecar next to mesh_path if it exists (nullopt if not); throws on malformed content,
// on a coordinate beyond +-bounds::kMeshCoord or a NaN, and on an mm_per_unit outside
// bounds::kMmPerUnit (0 or absent: detect the units), naming the file and the key.
std::optional<RefPointsSidecar> read_refpoints_sidecar(const std::string& mesh_path);
// The same checks on a sidecar's text (`path` names it in messages; the fuzzer's entry).
RefPointsSidecar parse_refpoints_sidecar(std::string_view text, const std::string& path);
std::string refpoints_sidecar_text(const RefPointsSidecar& sidecar);
void write_refpoints_sidecar(const std::string& mesh_path, const RefPointsSidecar& sidecar);

}  // namespace lorgnette::mesh
