// Cameras for try-on renders: look-at pinhole cameras and an orbit around a bounding box at the
// radius that frames it (the whole box inside the view for any azimuth), in the scene's OpenGL
// convention (kernels/common/camera_types.h: camera looks down -z, +y up).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "kernels/common/camera_types.h"

namespace lorgnette::render {

using Vec3 = std::array<float, 3>;

// Pinhole camera at `eye` looking at `target`; `up` need not be orthogonal to the view direction.
// Throws std::invalid_argument when eye == target, up is parallel to the view, or sizes are 0.
Camera look_at(const Vec3& eye, const Vec3& target, const Vec3& up, uint32_t width, uint32_t height,
               float fov_y_deg);

struct OrbitSpec {
  Vec3 center{0, 0, 0};
  Vec3 half_extent{1, 1, 1};  // half the box size: the radius frames its bounding sphere
  Vec3 front{0, 0, 1};        // direction from the centre to the first camera (the face's front)
  Vec3 up{0, 1, 0};
  uint32_t views = 1;  // evenly spaced azimuths, starting at yaw_start_deg (the front by default)
  // Azimuths (degrees about `up`, from `front` towards up x front) the orbit may take. The full
  // circle goes round once from yaw_start_deg; a narrower arc (the capture's, host/render/view_plan.h)
  // is swept at even steps from yaw_start_deg (clamped into the arc) to the max end, back to the min
  // end and back to the start, so an orbit video still loops.
  float yaw_min_deg = -180.0f, yaw_max_deg = 180.0f;
  float yaw_start_deg = 0.0f;  // the first view's azimuth (0: the front itself)
  float elevation_deg = 0.0f;
  float fov_y_deg = 30.0f;
  float margin = 1.05f;  // > 1 leaves a border around the framed sphere
  uint32_t width = 640, height = 480;
};

// The distance at which a sphere of `radius` fits the narrower field of view with `margin`.
float framing_distance(float radius, float fov_y_deg, uint32_t width, uint32_t height, float margin);

std::vector<Camera> orbit_cameras(const OrbitSpec& spec);

// The azimuth (degrees) of orbit view i (see OrbitSpec::yaw_min_deg).
float orbit_yaw_deg(const OrbitSpec& spec, uint32_t i);

// The capture's "front" and "up": the normalised mean of the cameras' backward (+z) and up (+y)
// axes, i.e. where the cameras were as seen from the subject. {0,0,1} / {0,1,0} when degenerate.
Vec3 front_from_cameras(const std::vector<Camera>& cams);
Vec3 up_from_cameras(const std::vector<Camera>& cams);

}  // namespace lorgnette::render
