// Views that stay where the capture looked: the model's view range (host/nerf/view_range.h, stored by
// `train`; for older models measured from the dataset the model names) and the one rule every planned
// view follows: yaw and pitch within the captured extremes plus kViewMarginDeg. `render --orbit`, the
// demo's orbit, `bench` and the viewer (viewer/orbit_control.h) all plan through here; a request
// beyond the range is clamped with a note saying so, unless the caller asks for views beyond the
// capture explicitly (`render --beyond-capture`, for the benchmark's "one angle beyond the arc").
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "host/nerf/model.h"
#include "host/nerf/view_range.h"
#include "host/render/orbit.h"

namespace lorgnette::render {

// The model's view range: the snapshot's, else measured from the cameras of the dataset the model
// names (models trained before the range was recorded), else nothing (with a warning). `source` (if
// given) says which, for logs.
std::optional<nerf::ViewRange> model_view_range(const nerf::NerfModel& model, std::string* source = nullptr);

struct OrbitRequest {
  uint32_t views = 1;
  float elevation_deg = 0.0f;
  std::optional<Vec3> front;    // the first view's direction from the centre (its tilt adds to elevation_deg)
  bool beyond_capture = false;  // the full circle at the requested elevation, whatever was captured
};

struct OrbitPlan {
  OrbitSpec spec;
  std::vector<std::string> notes;  // what was clamped or why no range applies; log them
};

// The orbit around `base` (centre, extent, size and field of view taken from it) for `request`,
// inside `range` widened by kViewMarginDeg: front and up from the range, azimuths swept over the
// allowed arc (the full circle when the range covers it) starting at request.front's yaw, and the
// elevation (plus request.front's tilt) clamped into the allowed pitch; a start or elevation outside
// is clamped with a note. Without a range, or with beyond_capture, the full circle as requested,
// starting at request.front. Throws std::invalid_argument for a zero or non-finite front.
OrbitPlan plan_orbit(const OrbitSpec& base, const std::optional<nerf::ViewRange>& range,
                     const OrbitRequest& request);

// Throws std::invalid_argument, naming --front, unless `front` is a finite non-zero direction.
void check_orbit_front(const Vec3& front);

// A note when `cam` looks from outside `range` widened by kViewMarginDeg ("" inside or without a
// range): explicit poses are rendered as given, but the user is told the view is a guess.
std::string pose_outside_note(const Camera& cam, const std::optional<nerf::ViewRange>& range);

}  // namespace lorgnette::render
