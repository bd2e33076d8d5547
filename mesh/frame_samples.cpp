// Samples of a frame's surface without its lenses (see frame_samples.h).
#include "mesh/frame_samples.h"

#include "mesh/canonical.h"
#include "mesh/refpoints.h"

namespace lorgnette::mesh {

std::vector<Eigen::Vector3f> sample_frame_surface(const TriMesh& mesh, int count, unsigned seed) {
  std::vector<bool> frame = lens_triangles(mesh);
  frame.flip();
  std::vector<Eigen::Vector3f> pts = sample_surface(mesh, count, seed, &frame);
  if (pts.empty()) pts = sample_surface(mesh, count, seed);
  return pts;
}

}  // namespace lorgnette::mesh
