// Dataset synthesis: renders a Subject from a sphere-cap camera rig and writes a training dataset
//   transforms.json     instant-ngp / nerfstudio (exact intrinsics and poses; per-frame depth_path)
//   images/NNNN.png     RGBA, straight alpha (transparent background) or opaque on a chosen colour;
//                       with a room: RGB, no alpha (the room is the background)
//   mattes/NNNN.png     with a room only: the subject's true matte (synth/matte.h), referenced from
//                       transforms.json frames as "eval_matte_path" (evaluation only)
//   depth/NNNN.exr      1 channel float: distance along the unit pixel-centre ray, dataset units,
//                       +inf where the ray misses the subject
//   ground_truth.json   source (mesh path or "procedural" + seed + params), mesh_to_dataset (4x4),
//                       mm_per_unit (null when unknown), landmarks and the 68 iBUG points in the
//                       dataset frame, per-view yaw/pitch, lighting and render settings; for the
//                       procedural head also iris_diameter_mm, pd_mm, face_width_temples_mm and
//                       temple_r/temple_l; with a card its corners (SynthOptions::card)
// The whole directory appears atomically, and --force replaces only an earlier synth output
// (host/util/output_folder.h).
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "synth/camera_rig.h"
#include "synth/room.h"
#include "synth/studio_render.h"
#include "synth/subject.h"

namespace lorgnette::synth {

struct SynthOptions {
  int views = 24;
  int width = 256, height = 256;
  float yaw_min_deg = -35.0f, yaw_max_deg = 35.0f;
  float pitch_min_deg = -12.0f, pitch_max_deg = 18.0f;
  uint64_t seed = 0;                          // camera placement seed
  std::optional<Eigen::Vector3f> background;  // linear RGB; empty = transparent
  int samples_per_axis = 3;
  float camera_distance = 3.0f;  // dataset units from the subject's look-at point
  bool force = false;            // replace an earlier synth output in the output directory
  StudioLighting lighting;
  // A room around the subject (synth/room.h; 0 = none). With a room the cameras are hand-held
  // phone cameras: a sweep along the yaw range, pitch/distance/aim jitter, fov_y_deg field of view,
  // at phone_distance_mm (converted with the subject's room scale) instead of camera_distance.
  int room = 0;
  float fov_y_deg = 60.0f;
  float phone_distance_mm = 480.0f;
  // The plain room's wall (room kPlainRoomLayout, synth/room.h): distance behind the eye point (mm)
  // and linear RGB albedo.
  float wall_mm = 1000.0f;
  Eigen::Vector3f wall_rgb{0.80f, 0.80f, 0.78f};
  // The plain room's window behind the subject (RoomPlacement::window): the views are then lit by
  // room_lighting(), not `lighting` alone (ground_truth.json "lighting" is what they were lit by).
  bool window = false;
  // With a room and a subject whose millimetres are known (the procedural head, or a mesh with its
  // mm_per_unit; a mesh's forehead is found from its shape): the subject holds an ID-1 card
  // (synth/card.h) flat against the forehead for the first half of the sweep (the views
  // 0 .. ceil(views / 2) - 1), a finger over its lower edge in every 4th of those views from the 2nd,
  // over its lower right corner in every 4th from the 4th. ground_truth.json "card" gives its corners
  // (dataset frame and per view pixels).
  bool card = false;
  std::function<void(int done, int total)> progress;  // called after each view
};

struct SynthReport {
  std::string directory;
  int views = 0;
  double seconds = 0.0;         // total wall time (rendering + writing)
  double render_seconds = 0.0;  // ray tracing only
};

// The subject and room `layout` (synth/room.h) as one mesh in the dataset frame; triangles
// [0, subject_triangles) are the subject's (what the matte counts).
struct RoomScene {
  mesh::TriMesh mesh;
  int subject_triangles = 0;
};
// `plain`: the plain room's wall (its layout is `layout`'s).
RoomScene subject_in_room(const Subject& subject, int layout, const RoomPlacement& plain = {});

// Linear RGB of rays that leave the room (it is open above and towards the cameras).
inline Eigen::Vector3f room_sky() { return {0.55f, 0.56f, 0.58f}; }

// The rig the options describe, aimed at the subject.
RigOptions rig_for(const Subject& subject, const SynthOptions& options);

// Throws std::runtime_error (nothing is left under out_dir) on bad options, unwritable output or
// Ctrl-C (host/util/interrupt.h).
SynthReport synthesize_dataset(const Subject& subject, const std::string& out_dir,
                               const SynthOptions& options);

}  // namespace lorgnette::synth
