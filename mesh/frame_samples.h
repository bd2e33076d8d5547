// The frame's surface as points: area-weighted random samples of the triangles that are not lenses
// (of every triangle for a lens-only mesh, which has nothing else to measure), with a fixed seed so
// one frame always gives the same points. The reference points, the temple hinges and the fit's
// contact probe all read the frame from such samples; this is the one rule for drawing them.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "mesh/trimesh.h"

namespace lorgnette::mesh {

std::vector<Eigen::Vector3f> sample_frame_surface(const TriMesh& mesh, int count, unsigned seed);

}  // namespace lorgnette::mesh
