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

constexpr int kRoomLayouts = 2;

struct RoomPlacement {
  int layout = 1;                                               // 1..kRoomLayouts
  Eigen::Matrix4f mm_to_dataset = Eigen::Matrix4f::Identity();  // room millimetres -> dataset frame
};

// Part name "room". Throws std::runtime_error for an unknown layout.
mesh::TriMesh make_room(const RoomPlacement& placement);

// Appends `src` with its positions transformed by `transform` (normals by its rotation) to `dst`,
// re-indexing materials, textures and parts.
void append_mesh(mesh::TriMesh& dst, const mesh::TriMesh& src, const Eigen::Matrix4f& transform);

}  // namespace lorgnette::synth
