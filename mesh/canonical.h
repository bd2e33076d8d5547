// Canonicalisation of a glasses mesh: the file's axes and units are mapped to the canonical frame
// (ARCHITECTURE.md: millimetres, x to the wearer's left, +y up, +z forward away from the face).
// Orientation comes from the geometry: the mirror-symmetry plane is x = 0, the longer of the two
// other extents is the depth (temples run backwards), the front is where geometry crosses the
// symmetry plane (the bridge), and up is where the temples leave the front (hinges sit high).
// Units: the file's declared unit if that gives a plausible total width, else mm / cm / m / inch,
// else the width is assumed to be 140 mm; the choice is reported, never silent.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "mesh/trimesh.h"

namespace lorgnette::mesh {

struct Canonicalization {
  Eigen::Matrix4f file_to_canonical = Eigen::Matrix4f::Identity();  // includes scale to mm
  Eigen::Matrix3f rotation = Eigen::Matrix3f::Identity();           // rows: canonical x, y, z in file axes
  double mm_per_unit = 1.0;
  std::string units;               // how the scale was chosen, for the user
  std::vector<std::string> notes;  // what was assumed or detected
  double symmetry_error_mm = 0.0;  // mean distance between the mesh and its mirror image
};

// Detects orientation and scale. The result maps to canonical axes and millimetres with the
// origin at the bounding-box centre (the caller moves the origin to g_c afterwards).
// `mm_per_unit_override` > 0 skips unit detection.
Canonicalization detect_canonical_frame(const TriMesh& mesh, double mm_per_unit_override = 0.0);

// Applies an affine transform to positions and (inverse-transpose) normals.
void transform_mesh(TriMesh& mesh, const Eigen::Matrix4f& transform);

// Area-weighted random surface points (fixed seed), optionally only of triangles whose part is
// (not) a lens; used by canonicalisation, reference points and measurements.
std::vector<Eigen::Vector3f> sample_surface(const TriMesh& mesh, int count, unsigned seed,
                                            const std::vector<bool>* triangle_mask = nullptr);

}  // namespace lorgnette::mesh
