// The render and orbit requests (host/render/render_settings.h): the one place their numbers are
// checked (host/util/bounds.h), the marcher's cap on samples per ray, and the orbit the settings
// plan being the one the front ends built by hand before (same cameras, to the bit).
#include "host/render/render_settings.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "host/render/analytic_field.h"
#include "host/render/render_job.h"
#include "host/render/renderer.h"
#include "host/util/bounds.h"
#include "tests/common/range_error.h"

namespace lorgnette::render {
namespace {

using lorgnette::testing::range_error;

TEST(RenderSettings, NumbersOutsideTheirRangeAreRefusedNamingFlagAndArgument) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  RenderSettings s;
  s.step_scale = 1e-9f;
  EXPECT_HAS(
      range_error([&] { render_options(s); }),
      "--step-scale (Python: step_scale) must be within 0.25..8 (marching step multiplier), found 1e-09");
  s = {};
  s.background = {1.0f, nan, 0.0f};
  EXPECT_HAS(range_error([&] { render_options(s); }),
             "--background (Python: background) must be within 0..1");
  s = {};
  s.spp = 0;
  EXPECT_HAS(range_error([&] { render_options(s); }), "--spp (Python: spp) must be within 1..64");
  s = {};
  s.surface_spp = 1000;
  EXPECT_HAS(range_error([&] { frame_options(s); }), "--surface-spp");
  EXPECT_NO_THROW(render_options(RenderSettings{}));
}

TEST(RenderSettings, DefaultsAreTheMarchersDefaults) {
  RenderOptions o = render_options(RenderSettings{}), d;
  EXPECT_EQ(o.spp, d.spp);
  EXPECT_EQ(o.step_scale, d.step_scale);
  EXPECT_EQ(o.background, d.background);
  EXPECT_EQ(o.alpha, d.alpha);
  EXPECT_EQ(o.marcher, d.marcher);
  EXPECT_EQ(o.max_samples_per_ray, d.max_samples_per_ray);
  EXPECT_EQ(frame_options(RenderSettings{}).surface_spp, FrameOptions{}.surface_spp);
}

TEST(OrbitSettings, HugeOrbitsAndBadAnglesAreRefusedBeforeAnyAllocation) {
  OrbitSettings s;
  s.views = 1000000000;
  EXPECT_HAS(range_error([&] { validate(s); }), "--orbit (Python: views) must be within 1..3600");
  s = {};
  s.views = 0;
  EXPECT_HAS(range_error([&] { validate(s); }), "--orbit");
  s = {};
  s.fov_y_deg = std::numeric_limits<float>::quiet_NaN();
  EXPECT_HAS(range_error([&] { validate(s); }), "--fov (Python: fov_y_deg)");
  s = {};
  s.elevation_deg = 95.0f;
  EXPECT_HAS(range_error([&] { validate(s); }), "--elevation");
  s = {};
  s.width = 0;
  EXPECT_HAS(range_error([&] { validate(s); }), "--size (Python: size) must be within 1..8192");
  EXPECT_THROW(check_glasses_and_placement(true, false), std::invalid_argument);
  EXPECT_THROW(check_glasses_and_placement(false, true), std::invalid_argument);
  EXPECT_NO_THROW(check_glasses_and_placement(true, true));
  EXPECT_NO_THROW(check_glasses_and_placement(false, false));
}

cl::Runtime& runtime() {
  static cl::Runtime rt;
  return rt;
}

// A step scale far below the range, or a damaged scene step, reaches the marcher only from code
// that skips the settings; the marcher refuses it at once instead of marching 10^9 samples a ray.
TEST(Marcher, RefusesStepsBeyondTheSamplesPerRayCap) {
  AnalyticField field(runtime(), {-1, -1, -1}, {1, 1, 1},
                      {analytic_box({-2, -2, -2}, {2, 2, 2}, 50.0f, {0.8f, 0.3f, 0.1f})}, 1024);
  VolumeScene scene;
  scene.aabb_min = {-1, -1, -1};
  scene.aabb_max = {1, 1, 1};
  scene.step = 0.01f;
  scene.field = &field;
  Camera cam = look_at({0.3f, 0.2f, 3.0f}, {0, 0, 0}, {0, 1, 0}, 16, 12, 30.0f);
  Marcher marcher(runtime());
  RenderOptions o;
  o.step_scale = 1e-9f;
  auto t0 = std::chrono::steady_clock::now();
  EXPECT_HAS(range_error([&] { marcher.render(scene, cam, nullptr, o); }), "steps across the box");
  scene.step = 1e-30f;
  o.step_scale = 1.0f;
  EXPECT_HAS(range_error([&] { marcher.render(scene, cam, nullptr, o); }), "retrain the model");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
  // Just inside the cap it still renders: a model step near the finest (diagonal / 16384) at step
  // scale 0.25 (diagonal / 16000 keeps clear of float rounding at the edge).
  scene.step = float(std::sqrt(12.0) / 16000.0);
  o.step_scale = 0.25f;
  RenderResult r = marcher.render(scene, cam, nullptr, o);  // dense: rays stop after ~0.2 units
  EXPECT_EQ(r.rays, 16u * 12u);
}

// The demo, `render --orbit` and Python's orbit() built this by hand; the settings give the same
// cameras, bit for bit.
TEST(OrbitSettings, PlanIsTheOrbitTheFrontEndsBuiltByHand) {
  field::FieldConfig config;
  config.log2_table_size = 10;
  config.finest_resolution = 32;
  nerf::Aabb box{{-0.4f, -0.5f, -0.3f}, {0.5f, 0.6f, 0.4f}};
  nerf::NerfModel model(runtime(), config, box, 16, 0.005f, 256, 1, true);
  std::vector<Camera> capture = {look_at({0.2f, 0.1f, 2.0f}, {0, 0, 0}, {0, 1, 0}, 32, 32, 40.0f),
                                 look_at({-0.6f, 0.3f, 1.8f}, {0, 0, 0}, {0, 1, 0}, 32, 32, 40.0f)};
  nerf::ViewRange range = nerf::view_range_from_cameras(capture, box.center());
  OrbitSettings s;
  s.views = 9, s.width = 64, s.height = 48, s.elevation_deg = 10.0f, s.fov_y_deg = 35.0f;
  OrbitSpec base = model_orbit(model, capture);
  base.width = 64, base.height = 48, base.fov_y_deg = 35.0f;
  OrbitRequest req;
  req.views = 9, req.elevation_deg = 10.0f;
  std::vector<Camera> by_hand = orbit_cameras(plan_orbit(base, range, req).spec);
  std::vector<Camera> planned = orbit_cameras(plan_model_orbit(model, s, range, capture).spec);
  ASSERT_EQ(planned.size(), by_hand.size());
  for (size_t i = 0; i < planned.size(); ++i)
    EXPECT_EQ(std::memcmp(&planned[i], &by_hand[i], sizeof(Camera)), 0) << "view " << i;
}

}  // namespace
}  // namespace lorgnette::render
