// A room around a synthetic subject, so synthetic captures look like phone captures at home: a
// floor, three walls (open towards the camera and the ceiling, so the studio key light still
// reaches the subject), and a few furniture boxes 0.4-3 m behind and beside the subject, all with
// procedural textures and lit by the same studio lighting as the subject. Layouts are numbered
// from 1 (kRoomLayouts of them). The room is built in millimetres around the subject's eye point
// (x to the subject's left, y up, z towards the cameras) and transformed into the dataset frame.
#pragma once
#include <Eigen/Core>

#include "mesh/trimesh.h"
#include "synth/studio_render.h"

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
  // A window in the plain wall behind the head (kWindowMm), glowing with daylight: the backlit
  // selfie, where the subject is a dark silhouette with a bright rim before a bright background.
  bool window = false;
};

// The window's rectangle in the plain wall, millimetres about the eye point (x to the subject's left,
// y up): wider and taller than a head's silhouette as a phone at 0.3-0.6 m projects it onto a wall up
// to 1.5 m behind (a head of 160 x 240 mm grows up to 4x there), so frontal views see the head
// against it.
struct WindowRect {
  float x0 = -800.0f, x1 = 800.0f, y0 = -600.0f, y1 = 1000.0f;
};
constexpr WindowRect kWindowMm{};
// The pane's offset in front of the wall (mm): the two surfaces never tie for a ray.
constexpr float kWindowPaneMm = 5.0f;
// The window's radiance, linear RGB: daylight (slightly bluer than the sRGB white point) two stops
// over the exposure's white, as a phone that exposes for the room sees a window: clipped to white in
// the 8-bit image, and bright enough to light the subject's outline from behind.
inline Eigen::Vector3f window_daylight() { return 4.0f * Eigen::Vector3f(0.93f, 0.97f, 1.0f); }

// The studio lighting of a room with a window behind the subject (`plain.window`): the key light is
// the window itself, from the eye point towards its centre, its disc as wide as the window's nearer
// edge and its strength what a Lambert surface facing it receives (radiance x solid angle / pi), and
// the front fill is a third of `front`'s (the room is lit by the window, not by lamps). With the
// studio's defaults the wall, facing away from the key, is then lit at most 0.21 + 0.10 x 0.75 =
// 0.29 of its albedo, so the window, even clipped to white, is at least kWindowOverWall times as
// bright as any wall, white included, and the face is lit more from behind than from the front.
// `front` unchanged without a window.
StudioLighting room_lighting(const RoomPlacement& plain, const StudioLighting& front);
constexpr float kWindowOverWall = 3.0f;

// Part name "room". Throws std::runtime_error for an unknown layout.
mesh::TriMesh make_room(const RoomPlacement& placement);

// Appends `src` with its positions transformed by `transform` (normals by its rotation) to `dst`,
// re-indexing materials, textures and parts.
void append_mesh(mesh::TriMesh& dst, const mesh::TriMesh& src, const Eigen::Matrix4f& transform);

}  // namespace lorgnette::synth
