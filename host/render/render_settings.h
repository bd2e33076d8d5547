// The render request and the orbit request as a user states them (the `lorgnette render` flags,
// Python's Model.render() and Model.orbit() arguments, the demo's orbit stage, the viewer's quality
// settings), with the CLI's defaults, and the one place their numbers are checked against
// host/util/bounds.h. render_options(), frame_options() and plan_model_orbit() turn them into what
// the marcher and the orbit planner take, so every front end renders alike and refuses alike.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "host/nerf/model.h"
#include "host/render/hybrid_frame.h"
#include "host/render/marcher.h"
#include "host/render/view_plan.h"

namespace lorgnette::render {

struct RenderSettings {
  uint32_t spp = 1;                   // NeRF rays per pixel
  uint32_t surface_spp = 4;           // glasses samples per pixel
  float step_scale = 1.0f;            // x the model's marching step (>1 faster, coarser)
  Vec3 background{1.0f, 1.0f, 1.0f};  // linear RGB, each channel 0..1
  bool alpha = false;
  std::string marcher = "auto";  // auto | wavefront | fused
};

// Throws OutOfRange (bounds.h) naming the flag and Python's argument.
void validate(const RenderSettings& settings);
RenderOptions render_options(const RenderSettings& settings);  // validates
FrameOptions frame_options(const RenderSettings& settings);    // validates; march + surface_spp

// Glasses need a placement and a placement needs glasses: without one of them, throws
// std::invalid_argument saying what to add (the CLI's flag and Python's argument), instead of
// drawing the frame at the identity (a slab of millimetres over the head) or nothing.
void check_glasses_and_placement(bool has_glasses, bool has_placement);

// A sphere an orbit frames instead of the model's whole box: the wearer's head (fit/head_framing.h),
// so the head fills the view even when the model's box also holds shoulders or a room.
struct FramedSphere {
  Vec3 center{0, 0, 0};
  float radius = 1.0f;  // scene units
};

struct OrbitSettings {
  uint32_t views = 1;
  uint32_t width = 854, height = 480;
  float fov_y_deg = 30.0f, elevation_deg = 0.0f;
  std::optional<Vec3> front;            // the first view's direction (default: the capture's mean camera)
  bool beyond_capture = false;          // the full circle, whatever the capture saw
  std::optional<FramedSphere> subject;  // what to frame (default: the model's box)
};

void validate(const OrbitSettings& settings);  // views, size, field of view, elevation, front

// The orbit around `model`'s box (or settings.subject) for `settings` (plan_orbit, view_plan.h) inside
// `range` (the model's view range; model_view_range gives it), facing the mean of `capture` when given and
// the range does not say. Validates; log the plan's notes.
OrbitPlan plan_model_orbit(const nerf::NerfModel& model, const OrbitSettings& settings,
                           const std::optional<nerf::ViewRange>& range,
                           const std::vector<Camera>& capture = {});

// The same for any base orbit (plan_model_orbit's is model_orbit(model, capture)): settings.subject
// replaces its centre and extent, settings its size, field of view and request. Validates.
OrbitPlan plan_settings_orbit(OrbitSpec base, const OrbitSettings& settings,
                              const std::optional<nerf::ViewRange>& range);

}  // namespace lorgnette::render
