// Cameras for dataset synthesis: pinhole cameras on a sphere cap around a target, looking at it,
// world +y up. Yaw turns about +y from the +z axis (positive yaw = camera towards +x, the wearer's
// left for a head facing +z); pitch raises the camera above the target. Views are spread over the
// (yaw, pitch) rectangle with a seeded low-discrepancy sequence, so any count covers it evenly.
// Hand-held mode imitates a phone swept once across the face: yaw in order along the arc with a
// little jitter, pitch wandering inside its range, distance and aim jittered, fixed phone field of view.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "common/camera_types.h"

namespace lorgnette::synth {

struct RigOptions {
  int views = 24;
  int width = 256, height = 256;
  float yaw_min_deg = -35.0f, yaw_max_deg = 35.0f;
  float pitch_min_deg = -12.0f, pitch_max_deg = 18.0f;
  uint64_t seed = 0;
  Eigen::Vector3f target{0, 0, 0};
  float distance = 3.0f;          // scene units from the target
  float frame_radius = 0.7f;      // scene units around the target that the view must contain (vertically)
  float fov_y_deg = 0.0f;         // vertical field of view; 0 = fit frame_radius at `distance`
  bool handheld = false;          // a sweep along the yaw range (see above) instead of the R2 cover
  float distance_jitter = 0.08f;  // hand-held: relative distance change (uniform +-)
  float aim_jitter = 0.05f;       // hand-held: look-at offset, in units of frame_radius (uniform +-)
};

// A camera at `eye` looking at `target` (up = world +y), vertical field of view fov_y (radians),
// principal point at the image centre, no distortion.
Camera look_at_camera(const Eigen::Vector3f& eye, const Eigen::Vector3f& target, int width, int height,
                      float fov_y);

// Camera position for (yaw, pitch) in degrees.
Eigen::Vector3f rig_position(const RigOptions& rig, float yaw_deg, float pitch_deg);

struct RigView {
  Camera camera;
  float yaw_deg, pitch_deg;
};

// Throws std::runtime_error on an empty or inverted range, a bad size or a non-positive distance.
std::vector<RigView> make_camera_rig(const RigOptions& rig);

// One camera of the rig at an explicit (yaw, pitch): the same intrinsics as make_camera_rig.
Camera rig_camera(const RigOptions& rig, float yaw_deg, float pitch_deg);

}  // namespace lorgnette::synth
