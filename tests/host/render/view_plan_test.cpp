// The capture's view range (host/nerf/view_range.h) and views planned inside it (view_plan.h):
// yaw/pitch measured from cameras placed at known angles, its snapshot round trip (old files without
// it still load, corrupt values are refused), the coverage advice, and orbits that sweep only the
// captured arc with a clamped elevation unless views beyond the capture are asked for.
#include "host/render/view_plan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "host/nerf/snapshot.h"
#include "host/render/orbit.h"

namespace {

using namespace lorgnette;
constexpr float kDeg = 3.14159265f / 180.0f;

// A camera `dist` from `center` at yaw/pitch degrees about +y from +z, looking at the centre.
Camera camera_at(float yaw, float pitch, float dist = 3.0f, render::Vec3 center = {0, 0, 0}) {
  render::Vec3 eye = {center[0] + dist * std::cos(pitch * kDeg) * std::sin(yaw * kDeg),
                      center[1] + dist * std::sin(pitch * kDeg),
                      center[2] + dist * std::cos(pitch * kDeg) * std::cos(yaw * kDeg)};
  return render::look_at(eye, center, {0, 1, 0}, 64, 48, 30.0f);
}

// Cameras every 5 deg of yaw in [lo, hi], each at pitch +p and -p (so the mean up is exactly +y).
std::vector<Camera> arc(float lo, float hi, float p, render::Vec3 center = {0, 0, 0}) {
  std::vector<Camera> cams;
  for (float yaw = lo; yaw <= hi + 1e-3f; yaw += 5.0f)
    for (float s : {-1.0f, 1.0f}) cams.push_back(camera_at(yaw, s * p, 3.0f, center));
  return cams;
}

TEST(ViewRange, MeasuresTheCamerasYawAndPitchAboutTheCentre) {
  render::Vec3 c = {0.2f, -0.1f, 0.3f};
  nerf::ViewRange r = nerf::view_range_from_cameras(arc(-40, 40, 12, c), c);
  ASSERT_TRUE(r.valid());
  // Tolerance 0.01 deg: float camera positions.
  EXPECT_NEAR(r.yaw_min, -40.0, 0.01);
  EXPECT_NEAR(r.yaw_max, 40.0, 0.01);
  EXPECT_NEAR(r.pitch_min, -12.0, 0.01);
  EXPECT_NEAR(r.pitch_max, 12.0, 0.01);
  EXPECT_EQ(r.cameras, 34u);
  EXPECT_NEAR(r.front[2], 1.0f, 1e-5f);
  EXPECT_NEAR(r.up[1], 1.0f, 1e-5f);
  // direction_at and yaw_pitch_of are inverses.
  auto d = nerf::direction_at(r, 25.0, -7.0);
  auto yp = nerf::yaw_pitch_of(r, {c[0] + 2 * d[0], c[1] + 2 * d[1], c[2] + 2 * d[2]});
  EXPECT_NEAR(yp[0], 25.0, 1e-3);
  EXPECT_NEAR(yp[1], -7.0, 1e-3);
  EXPECT_THROW(nerf::view_range_from_cameras({}, c), std::invalid_argument);
}

TEST(ViewRange, AFullCircleCaptureCoversEveryYaw) {
  std::vector<Camera> cams;
  for (float yaw = -180; yaw < 180; yaw += 10) cams.push_back(camera_at(yaw, 20));
  nerf::ViewRange r = nerf::view_range_from_cameras(cams, {0, 0, 0});
  ASSERT_TRUE(r.valid());
  EXPECT_LE(r.yaw_min, -170.0);
  EXPECT_GE(r.yaw_max, 170.0);
  EXPECT_NEAR(r.widened().yaw_max - r.widened().yaw_min, 360.0, 1e-9);
}

TEST(ViewRange, NarrowArcsGetAdviceWideOnesDoNot) {
  nerf::ViewRange narrow = nerf::view_range_from_cameras(arc(-15, 15, 5), {0, 0, 0});
  std::string advice = nerf::coverage_advice(narrow);
  EXPECT_NE(advice.find("Film from ear to ear"), std::string::npos) << advice;
  EXPECT_NE(advice.find("35"), std::string::npos) << advice;
  // One side only: still too narrow (the other ear is never seen).
  nerf::ViewRange one_side = narrow;
  one_side.yaw_min = -5, one_side.yaw_max = 80;
  EXPECT_FALSE(nerf::coverage_advice(one_side).empty());
  nerf::ViewRange wide = nerf::view_range_from_cameras(arc(-40, 40, 5), {0, 0, 0});
  EXPECT_EQ(nerf::coverage_advice(wide), "");
}

nerf::Snapshot tiny_snapshot() {
  nerf::Snapshot s;
  s.config.levels = 1;
  s.config.features_per_level = 1;
  s.config.log2_table_size = 8;
  s.config.base_resolution = s.config.finest_resolution = 2;
  s.config.density_hidden = s.config.geo_features = s.config.color_hidden = 1;
  s.config.color_hidden_layers = s.config.sh_degree = 1;
  s.step = 0.01f;
  s.params.assign(s.config.param_count(), 0.01f);
  s.occ = nerf::full_occupancy(2);
  return s;
}

TEST(ViewRange, RoundTripsThroughTheSnapshotAndOldFilesStillLoad) {
  nerf::Snapshot s = tiny_snapshot();
  nerf::Snapshot old = nerf::parse_snapshot(nerf::encode_snapshot(s), "old.lnerf");
  EXPECT_FALSE(old.view_range.has_value());
  s.view_range = nerf::view_range_from_cameras(arc(-30, 50, 8), {0.1f, 0.2f, 0.3f});
  nerf::Snapshot back = nerf::parse_snapshot(nerf::encode_snapshot(s), "new.lnerf");
  ASSERT_TRUE(back.view_range.has_value());
  EXPECT_NEAR(back.view_range->yaw_min, s.view_range->yaw_min, 1e-9);
  EXPECT_NEAR(back.view_range->pitch_max, s.view_range->pitch_max, 1e-9);
  EXPECT_EQ(back.view_range->center, s.view_range->center);
  EXPECT_EQ(back.view_range->cameras, s.view_range->cameras);
  // Corrupt ranges are refused with the field's name, never half-loaded.
  for (auto [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"\"up\":[", "\"up\":[5,"}, {"\"yaw_deg\":[", "\"yaw_deg\":[900,"}}) {
    std::string bytes = nerf::encode_snapshot(s);
    uint64_t hlen = 0;
    std::memcpy(&hlen, bytes.data() + 8, 8);
    std::string header = bytes.substr(16, hlen);
    size_t at = header.find(from);
    ASSERT_NE(at, std::string::npos) << header;
    header.replace(at, from.size(), to);
    // Drop the entry's old first value so the arrays keep their length: "[5,x,y,z]" -> "[5,y,z]".
    size_t comma = header.find(',', at + to.size());
    header.erase(at + to.size(), comma - (at + to.size()) + 1);
    uint64_t n = header.size();
    std::string edited = bytes.substr(0, 8) + std::string(reinterpret_cast<const char*>(&n), 8) + header +
                         bytes.substr(16 + hlen);
    try {
      nerf::parse_snapshot(edited, "bad.lnerf");
      ADD_FAILURE() << "accepted " << header;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("view_range"), std::string::npos) << e.what();
    }
  }
}

render::OrbitSpec base_orbit() {
  render::OrbitSpec o;
  o.half_extent = {0.5f, 0.5f, 0.5f};
  o.width = 64;
  o.height = 48;
  return o;
}

TEST(ViewPlan, OrbitsSweepOnlyTheCapturedArcPlusTheMargin) {
  nerf::ViewRange r = nerf::view_range_from_cameras(arc(-30, 40, 6), {0, 0, 0});
  render::OrbitRequest req;
  req.views = 48;
  req.elevation_deg = 45.0f;  // above the captured pitch (6 + 10 margin)
  render::OrbitPlan plan = render::plan_orbit(base_orbit(), r, req);
  EXPECT_NEAR(plan.spec.elevation_deg, 16.0, 0.01);
  ASSERT_GE(plan.notes.size(), 2u);
  double ymin = 1e9, ymax = -1e9;
  for (const Camera& c : render::orbit_cameras(plan.spec)) {
    auto yp = nerf::yaw_pitch_of(r, {c.c2w[3], c.c2w[7], c.c2w[11]});
    ymin = std::min(ymin, yp[0]), ymax = std::max(ymax, yp[0]);
    EXPECT_NEAR(yp[1], 16.0, 0.01);
    EXPECT_EQ(render::pose_outside_note(c, r), "");
  }
  // Yaw is measured from the capture's mean direction (the arc's middle, 5 deg): -35..+35.
  EXPECT_NEAR(r.yaw_min, -35.0, 0.01);
  EXPECT_NEAR(r.yaw_max, 35.0, 0.01);
  // 48 views at even steps over the arc reach both ends of the widened range (to one step, 5 deg).
  EXPECT_GE(ymin, -45.01);
  EXPECT_LE(ymax, 45.01);
  EXPECT_LT(ymin, -45.0 + 5.1);
  EXPECT_GT(ymax, 45.0 - 5.1);
  // The first view is the capture's front.
  auto first = render::orbit_cameras(plan.spec)[0];
  EXPECT_NEAR(nerf::yaw_pitch_of(r, {first.c2w[3], first.c2w[7], first.c2w[11]})[0], 0.0, 0.01);
}

TEST(ViewPlan, BeyondTheCaptureIsTheFullCircleAndPosesOutsideAreFlagged) {
  nerf::ViewRange r = nerf::view_range_from_cameras(arc(-30, 40, 6), {0, 0, 0});
  render::OrbitRequest req;
  req.views = 12;
  req.elevation_deg = 45.0f;
  req.beyond_capture = true;
  render::OrbitPlan plan = render::plan_orbit(base_orbit(), r, req);
  EXPECT_EQ(plan.spec.elevation_deg, 45.0f);
  EXPECT_EQ(plan.spec.yaw_max_deg - plan.spec.yaw_min_deg, 360.0f);
  ASSERT_EQ(plan.notes.size(), 1u);
  EXPECT_NE(plan.notes[0].find("beyond the capture"), std::string::npos);
  int outside = 0;
  for (const Camera& c : render::orbit_cameras(plan.spec))
    outside += !render::pose_outside_note(c, r).empty();
  EXPECT_EQ(outside, 12);  // at 45 deg of elevation every view is above the captured pitch
  // One angle beyond the arc's end (40 + 10 margin, in the capture's frame 35 + 10), at the captured
  // pitch: flagged; just inside the margin: not.
  EXPECT_FALSE(render::pose_outside_note(camera_at(55, 0), r).empty());
  EXPECT_EQ(render::pose_outside_note(camera_at(48, 0), r), "");
  // Without a range, the full circle as requested (and a note saying why).
  render::OrbitPlan none = render::plan_orbit(base_orbit(), std::nullopt, {12, 30.0f, std::nullopt, false});
  EXPECT_EQ(none.spec.elevation_deg, 30.0f);
  EXPECT_EQ(none.spec.yaw_max_deg - none.spec.yaw_min_deg, 360.0f);
  EXPECT_EQ(none.notes.size(), 1u);
}

TEST(ViewPlan, TheArcSweepLoopsFromTheFrontAtEvenSteps) {
  render::OrbitSpec s = base_orbit();
  s.yaw_min_deg = -20, s.yaw_max_deg = 40, s.views = 12;  // path length 120 deg: 10 deg a step
  std::vector<float> expect = {0, 10, 20, 30, 40, 30, 20, 10, 0, -10, -20, -10};
  for (uint32_t i = 0; i < 12; ++i) EXPECT_NEAR(render::orbit_yaw_deg(s, i), expect[i], 1e-4) << i;
  s.yaw_min_deg = -180, s.yaw_max_deg = 180;
  EXPECT_NEAR(render::orbit_yaw_deg(s, 3), 90.0f, 1e-4);  // the full circle: once round
  // From another start: start -> max -> min -> start, and the full circle from there.
  s.yaw_min_deg = -20, s.yaw_max_deg = 40, s.yaw_start_deg = 20;
  expect = {20, 30, 40, 30, 20, 10, 0, -10, -20, -10, 0, 10};
  for (uint32_t i = 0; i < 12; ++i) EXPECT_NEAR(render::orbit_yaw_deg(s, i), expect[i], 1e-4) << i;
  s.yaw_min_deg = -180, s.yaw_max_deg = 180, s.yaw_start_deg = 30;
  EXPECT_NEAR(render::orbit_yaw_deg(s, 3), 120.0f, 1e-4);
}

std::array<double, 2> yaw_pitch(const nerf::ViewRange& r, const Camera& c) {
  return nerf::yaw_pitch_of(r, {c.c2w[3], c.c2w[7], c.c2w[11]});
}

TEST(ViewPlan, AFrontInsideTheCapturedArcStartsTheOrbitThere) {
  // `render --front` without --beyond-capture: the user's start is honoured inside the arc.
  nerf::ViewRange r = nerf::view_range_from_cameras(arc(-30, 40, 6), {0, 0, 0});
  render::OrbitRequest req;
  req.views = 12;
  req.elevation_deg = 3.0f;
  req.front = nerf::direction_at(r, 20.0, 5.0);  // yaw 20, tilted up 5 deg
  render::OrbitPlan plan = render::plan_orbit(base_orbit(), r, req);
  ASSERT_EQ(plan.notes.size(), 1u);  // the arc, not the full circle; nothing about --front
  EXPECT_EQ(plan.notes[0].find("--front"), std::string::npos) << plan.notes[0];
  std::vector<Camera> cams = render::orbit_cameras(plan.spec);
  EXPECT_NEAR(yaw_pitch(r, cams[0])[0], 20.0, 0.01);
  EXPECT_NEAR(yaw_pitch(r, cams[0])[1], 8.0, 0.01);  // the front's tilt plus --elevation
  double ymin = 1e9, ymax = -1e9;
  for (const Camera& c : cams) {
    ymin = std::min(ymin, yaw_pitch(r, c)[0]), ymax = std::max(ymax, yaw_pitch(r, c)[0]);
    EXPECT_EQ(render::pose_outside_note(c, r), "");
  }
  EXPECT_LT(ymin, -45.0 + 15.1);  // still the whole widened arc -45..+45, to one step (15 deg)
  EXPECT_GT(ymax, 45.0 - 15.1);
}

TEST(ViewPlan, AFrontOutsideTheCapturedArcIsClampedWithANote) {
  nerf::ViewRange r = nerf::view_range_from_cameras(arc(-30, 40, 6), {0, 0, 0});
  render::OrbitRequest req;
  req.views = 4;
  req.front = nerf::direction_at(r, 90.0, 30.0);  // beside the head and well above the capture
  render::OrbitPlan plan = render::plan_orbit(base_orbit(), r, req);
  ASSERT_EQ(plan.notes.size(), 3u);
  EXPECT_NE(plan.notes[0].find("--front is at yaw +90"), std::string::npos) << plan.notes[0];
  EXPECT_NE(plan.notes[0].find("starting at +45"), std::string::npos) << plan.notes[0];
  EXPECT_NE(plan.notes[0].find("--beyond-capture"), std::string::npos) << plan.notes[0];
  EXPECT_NE(plan.notes[1].find("tilt of --front"), std::string::npos) << plan.notes[1];
  Camera first = render::orbit_cameras(plan.spec)[0];
  EXPECT_NEAR(yaw_pitch(r, first)[0], 45.0, 0.01);
  EXPECT_NEAR(yaw_pitch(r, first)[1], 16.0, 0.01);  // 6 + 10 margin
  // Beyond the capture the front is the orbit's, as given.
  req.beyond_capture = true;
  Camera beyond = render::orbit_cameras(render::plan_orbit(base_orbit(), r, req).spec)[0];
  EXPECT_NEAR(yaw_pitch(r, beyond)[0], 90.0, 0.01);
  EXPECT_NEAR(yaw_pitch(r, beyond)[1], 30.0, 0.01);
  // A front that is no direction is refused, with or without a range.
  req.front = render::Vec3{0, 0, 0};
  EXPECT_THROW(render::plan_orbit(base_orbit(), r, req), std::invalid_argument);
  EXPECT_THROW(render::plan_orbit(base_orbit(), std::nullopt, req), std::invalid_argument);
}

}  // namespace
