// RenderSettings / OrbitSettings -> marcher options and orbit plans, with the bounds checks
// (render_settings.h).
#include "host/render/render_settings.h"

#include <cmath>
#include <stdexcept>

#include "host/render/fused_marcher.h"
#include "host/render/renderer.h"
#include "host/util/bounds.h"

namespace lorgnette::render {
namespace b = bounds;

void validate(const RenderSettings& s) {
  check_bound(b::kSpp, s.spp);
  check_bound(b::kSurfaceSpp, s.surface_spp);
  check_bound(b::kStepScale, s.step_scale);
  for (float c : s.background) check_bound(b::kBackground, c);
  parse_marcher_kind(s.marcher);  // throws naming the choices
}

RenderOptions render_options(const RenderSettings& s) {
  validate(s);
  RenderOptions o;
  o.spp = s.spp;
  o.step_scale = s.step_scale;
  o.background = s.background;
  o.alpha = s.alpha;
  o.marcher = parse_marcher_kind(s.marcher);
  return o;
}

FrameOptions frame_options(const RenderSettings& s) {
  FrameOptions f;
  f.march = render_options(s);
  f.surface_spp = s.surface_spp;
  return f;
}

void check_glasses_and_placement(bool has_glasses, bool has_placement) {
  if (has_glasses && !has_placement)
    throw std::invalid_argument(
        "glasses were given but no placement: add --placement P.json from `lorgnette fit`, or --transform "
        "or --translate/--rotate/--scale (Python: placement=a Placement or a 4x4 canonical mm -> scene)");
  if (has_placement && !has_glasses)
    throw std::invalid_argument(
        "a placement was given but no glasses: add --glasses FRAME (Python: glasses=Glasses.load(FRAME))");
}

void validate(const OrbitSettings& s) {
  check_bound(b::kOrbitViews, s.views);
  check_bound(b::kImageSide, s.width);
  check_bound(b::kImageSide, s.height);
  check_bound(b::kFovDeg, s.fov_y_deg);
  check_bound(b::kElevationDeg, s.elevation_deg);
  if (s.front) check_orbit_front(*s.front);
  if (s.subject) {
    const FramedSphere& f = *s.subject;
    const bool finite =
        std::isfinite(f.center[0]) && std::isfinite(f.center[1]) && std::isfinite(f.center[2]);
    if (!finite || !(f.radius > 0.0f) || !std::isfinite(f.radius))
      throw std::invalid_argument("the framed subject needs a finite centre and a positive radius");
  }
}

OrbitPlan plan_model_orbit(const nerf::NerfModel& model, const OrbitSettings& s,
                           const std::optional<nerf::ViewRange>& range, const std::vector<Camera>& capture) {
  return plan_settings_orbit(model_orbit(model, capture), s, range);
}

OrbitPlan plan_settings_orbit(OrbitSpec base, const OrbitSettings& s,
                              const std::optional<nerf::ViewRange>& range) {
  validate(s);
  if (s.subject) {
    // OrbitSpec frames the sphere around its half extent: a cube's half diagonal of radius r.
    const float h = s.subject->radius / std::sqrt(3.0f);
    base.center = s.subject->center;
    base.half_extent = {h, h, h};
  }
  base.fov_y_deg = s.fov_y_deg;
  base.width = s.width;
  base.height = s.height;
  OrbitRequest req;
  req.views = s.views;
  req.elevation_deg = s.elevation_deg;
  req.front = s.front;
  req.beyond_capture = s.beyond_capture;
  return plan_orbit(base, range, req);
}

}  // namespace lorgnette::render
