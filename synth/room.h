// A room around a synthetic subject, so synthetic captures look like phone captures at home: a
// floor, three walls (open towards the camera and the ceiling, so the studio key light still
// reaches the subject), and a few furniture boxes 0.4-3 m behind and beside the subject, all with
// procedural textures and lit by the same studio lighting as the subject. Layouts are numbered
// from 1 (kRoomLayouts of them). The room is built in millimetres around the subject's eye point
// (x to the subject's left, y up, z towards the cameras) and transformed into the dataset frame.
#pragma once
#include <Eigen/Core>

#include "mesh/trimesh.h"

namespace lorgnette::synth {

constexpr int kRoomLayouts = 3;
// Layout 3 is a plain room: one wall of one colour `wall_mm` behind the eye point, without texture
// or furniture, and a floor of the same paint: the home of most shoppers' selfies, and the case
// where colour cannot tell a pale face from the wall behind it (#41). Layouts 1 and 2 are textured.
constexpr int kPlainRoomLayout = 3;

struct RoomPlacement {
  int layout = 1;                                               // 1..kRoomLayouts
  Eigen::Matrix4f mm_to_dataset = Eigen::Matrix4f::Identity();  // room millimetres -> dataset frame
  // The plain room's wall (layout kPlainRoomLayout only): its distance behind the eye point (mm) and
  // its linear RGB albedo.
  float wall_mm = 1000.0f;
  Eigen::Vector3f wall_rgb{0.80f, 0.80f, 0.78f};
};

// Part name "room". Throws std::runtime_error for an unknown layout.
mesh::TriMesh make_room(const RoomPlacement& placement);

// Appends `src` with its positions transformed by `transform` (normals by its rotation) to `dst`,
// re-indexing materials, textures and parts.
void append_mesh(mesh::TriMesh& dst, const mesh::TriMesh& src, const Eigen::Matrix4f& transform);

}  // namespace lorgnette::synth
