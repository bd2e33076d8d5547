// Planning views inside the capture's view range (see view_plan.h).
#include "host/render/view_plan.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>

#include "host/render/renderer.h"

namespace lorgnette::render {

std::optional<nerf::ViewRange> model_view_range(const nerf::NerfModel& model, std::string* source) {
  auto say = [&](std::string s) {
    if (source) *source = std::move(s);
  };
  if (model.view_range) {
    say(fmt::format("the model ({} training cameras)", model.view_range->cameras));
    return model.view_range;
  }
  std::vector<Camera> cams = capture_cameras(model);  // warns itself when the dataset is unreadable
  if (cams.empty()) {
    say("unknown (the model records no view range and names no readable dataset)");
    spdlog::warn(
        "the model does not record the directions its capture looked from and its dataset cannot be read: "
        "views are not limited to the captured arc (retrain with this version to record them)");
    return std::nullopt;
  }
  const auto& n = model.normalisation;  // dataset frame -> model frame
  for (Camera& c : cams)
    for (int k = 0; k < 3; ++k) c.c2w[4 * k + 3] = c.c2w[4 * k + 3] * n.scale + n.offset[k];
  say(fmt::format("the dataset's {} cameras (the model predates recorded view ranges)", cams.size()));
  return nerf::view_range_from_cameras(cams, model.aabb().center());
}

OrbitPlan plan_orbit(const OrbitSpec& base, const std::optional<nerf::ViewRange>& range,
                     const OrbitRequest& request) {
  OrbitPlan plan;
  plan.spec = base;
  OrbitSpec& s = plan.spec;
  s.views = request.views;
  s.elevation_deg = request.elevation_deg;
  if (request.front) s.front = *request.front;
  if (!range) {
    plan.notes.push_back("no view range known: a full orbit, not limited to what the capture saw");
    return plan;
  }
  nerf::ViewRange allowed = range->widened();
  if (request.beyond_capture) {
    plan.notes.push_back(fmt::format(
        "views beyond the capture (asked for): the capture saw yaw {:+.0f}..{:+.0f} and pitch "
        "{:+.0f}..{:+.0f} "
        "deg; views more than {:.0f} deg beyond that show the model's guesses",
        range->yaw_min, range->yaw_max, range->pitch_min, range->pitch_max, nerf::kViewMarginDeg));
    return plan;
  }
  s.front = range->front;
  s.up = range->up;
  if (request.front)
    plan.notes.push_back(
        "--front is ignored inside the captured arc (the orbit starts at the capture's mean direction); "
        "add --beyond-capture to start elsewhere");
  s.yaw_min_deg = float(allowed.yaw_min);
  s.yaw_max_deg = float(allowed.yaw_max);
  float clamped = std::clamp(request.elevation_deg, float(allowed.pitch_min), float(allowed.pitch_max));
  if (clamped != request.elevation_deg)
    plan.notes.push_back(fmt::format(
        "elevation {:.0f} deg is outside the captured pitch {:+.0f}..{:+.0f} deg (with a {:.0f} deg "
        "margin): using {:.0f} deg (add --beyond-capture to keep it)",
        request.elevation_deg, allowed.pitch_min, allowed.pitch_max, nerf::kViewMarginDeg, clamped));
  s.elevation_deg = clamped;
  if (s.yaw_max_deg - s.yaw_min_deg < 359.999f)
    plan.notes.push_back(fmt::format(
        "the orbit sweeps the captured arc, yaw {:+.0f}..{:+.0f} deg (with a {:.0f} deg margin), not the "
        "full circle (add --beyond-capture for the full circle)",
        allowed.yaw_min, allowed.yaw_max, nerf::kViewMarginDeg));
  return plan;
}

std::string pose_outside_note(const Camera& cam, const std::optional<nerf::ViewRange>& range) {
  if (!range) return "";
  nerf::ViewRange allowed = range->widened();
  auto yp = nerf::yaw_pitch_of(*range, {cam.c2w[3], cam.c2w[7], cam.c2w[11]});
  const double slack = 0.01;  // degrees: planned views on the boundary, through float positions
  if (yp[0] >= allowed.yaw_min - slack && yp[0] <= allowed.yaw_max + slack &&
      yp[1] >= allowed.pitch_min - slack && yp[1] <= allowed.pitch_max + slack)
    return "";
  return fmt::format(
      "this view (yaw {:+.0f}, pitch {:+.0f} deg) looks from outside the captured directions (yaw "
      "{:+.0f}..{:+.0f}, pitch {:+.0f}..{:+.0f} deg with margin): what it shows there is the model's guess",
      yp[0], yp[1], allowed.yaw_min, allowed.yaw_max, allowed.pitch_min, allowed.pitch_max);
}

}  // namespace lorgnette::render
