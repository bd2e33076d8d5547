// Planning views inside the capture's view range (see view_plan.h).
#include "host/render/view_plan.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "host/render/renderer.h"

namespace lorgnette::render {
namespace {
std::array<float, 3> add(const std::array<float, 3>& a, const Vec3& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
}  // namespace

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

void check_orbit_front(const Vec3& f) {
  float n2 = f[0] * f[0] + f[1] * f[1] + f[2] * f[2];
  if (!std::isfinite(n2) || n2 <= 0.0f)
    throw std::invalid_argument(
        fmt::format("--front {} {} {} is not a direction: give three numbers, not all zero (e.g. 0 0 1)",
                    f[0], f[1], f[2]));
}

OrbitPlan plan_orbit(const OrbitSpec& base, const std::optional<nerf::ViewRange>& range,
                     const OrbitRequest& request) {
  OrbitPlan plan;
  plan.spec = base;
  OrbitSpec& s = plan.spec;
  s.views = request.views;
  s.elevation_deg = request.elevation_deg;
  if (request.front) {
    check_orbit_front(*request.front);
    s.front = *request.front;
  }
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
  s.yaw_min_deg = float(allowed.yaw_min);
  s.yaw_max_deg = float(allowed.yaw_max);
  float elevation = request.elevation_deg;
  if (request.front) {
    // The requested start in the range's frame: its yaw starts the sweep, its tilt adds to the
    // elevation (as it does beyond the capture, where the orbit's front is the request itself).
    std::array<double, 2> yp = nerf::yaw_pitch_of(*range, add(range->center, *request.front));
    float yaw = std::clamp(float(yp[0]), s.yaw_min_deg, s.yaw_max_deg);
    if (yaw != float(yp[0]))
      plan.notes.push_back(fmt::format(
          "--front is at yaw {:+.0f} deg, outside the captured arc {:+.0f}..{:+.0f} deg (with a {:.0f} deg "
          "margin): starting at {:+.0f} deg (add --beyond-capture to keep it)",
          yp[0], allowed.yaw_min, allowed.yaw_max, nerf::kViewMarginDeg, yaw));
    s.yaw_start_deg = yaw;
    elevation += float(yp[1]);
  }
  float clamped = std::clamp(elevation, float(allowed.pitch_min), float(allowed.pitch_max));
  if (clamped != elevation)
    plan.notes.push_back(fmt::format(
        "elevation {:.0f} deg{} is outside the captured pitch {:+.0f}..{:+.0f} deg (with a {:.0f} deg "
        "margin): using {:.0f} deg (add --beyond-capture to keep it)",
        elevation, request.front ? " (--elevation plus the tilt of --front)" : "", allowed.pitch_min,
        allowed.pitch_max, nerf::kViewMarginDeg, clamped));
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
