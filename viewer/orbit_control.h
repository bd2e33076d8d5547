// The viewer's camera: an orbit around the head's box in the capture's frame (front = where the
// cameras were, up = their mean up), with yaw/pitch limited to the directions the capture saw (a NeRF
// shows nonsense from where no camera looked), distance as a factor of the framing distance and a
// bounded pan. Limits come from the dataset's cameras when the model names its dataset, else a
// default of ±60° yaw and ±30° pitch.
#pragma once
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "host/nerf/view_range.h"
#include "host/render/orbit.h"

namespace lorgnette::viewer {

struct OrbitFrame {
  render::Vec3 center{0, 0, 0};
  render::Vec3 front{0, 0, 1}, up{0, 1, 0}, right{1, 0, 0};  // orthonormal, right = up x front
  float radius = 1.0f;                                       // framed sphere (scene units)
  float fov_y_deg = 30.0f;
  float margin = 1.05f;  // x the distance that just frames the sphere (render::OrbitSpec::margin)
};

struct OrbitLimits {
  double yaw_min = -60, yaw_max = 60, pitch_min = -30, pitch_max = 30;  // degrees
  double distance_min = 0.55, distance_max = 2.0;                       // x framing distance
  double pan_max = 0.5;                                                 // x radius
  std::string source = "default";                                       // "capture (N cameras)" or "default"
};

struct OrbitState {
  double yaw_deg = 0, pitch_deg = 0, distance = 1, pan_x = 0, pan_y = 0;
};

// The frame of a planned orbit (render::plan_model_orbit, the request every front end makes): its
// centre, the sphere round its box, its field of view and margin, and an orthonormal front and up
// (the spec's need not be orthogonal). The start state (yaw 0, pitch 0, distance 1, no pan) is then
// the spec's first camera at elevation 0, so the viewer opens on the view `render --orbit` starts at.
OrbitFrame make_orbit_frame(const render::OrbitSpec& spec);

// The limits of a capture's view range (host/nerf/view_range.h, the rule render::plan_orbit follows
// too): its yaw/pitch extremes widened by `margin_deg`, at least `min_span_deg` wide and holding the
// start view (0, 0); the default limits when no range is known.
OrbitLimits limits_from_range(const std::optional<nerf::ViewRange>& range,
                              double margin_deg = nerf::kViewMarginDeg, double min_span_deg = 20.0);

OrbitState clamp_orbit(const OrbitState& s, const OrbitLimits& limits);

// The pinhole camera of an orbit state (no distortion), width x height pixels.
Camera orbit_camera(const OrbitFrame& frame, const OrbitState& s, uint32_t width, uint32_t height);

// A crop of a camera's image: rows [y0, y0 + rows) as a camera of that height (the principal point
// moves), so a frame can be rendered in bands.
Camera crop_rows(const Camera& cam, uint32_t y0, uint32_t rows);

nlohmann::json to_json(const OrbitLimits& l);

}  // namespace lorgnette::viewer
