// Holes in a subject's solid regions (host/nerf/subject_holes.h) on an analytic scene: an opaque
// sphere whose front cap is the "face" (points on the sphere within 50 deg of +z). Whole, no ray
// through the cap's hull is transparent; with a cylindrical tunnel punched through it along the
// view axis, the share of hole rays from a distant frontal camera is the tunnel's cross-section over
// the shrunk hull's area (a disc of radius 0.85 x sin(50 deg) x R in an orthographic view; at the
// camera's 40 units perspective narrows the tunnel's through-rays and widens the hull by ~3 % in
// area together), and the head counts as broken.
// Views behind the face are not judged, and the advice says what to film differently. A convex solid
// inside the subject is judged whole from any side, each region on its own share.
#include "host/nerf/subject_holes.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kernels/train/occupancy.h"
#include "synthetic_scene.h"

namespace lorgnette::nerf {
namespace {

constexpr float kRadius = 0.5f, kSigma = 400.0f, kStep = 0.004f;

struct Scene {
  Aabb box{{-1.0f, -1.0f, -1.0f}, {1.0f, 1.0f, 1.0f}};
  OccupancyGrid occ;
  float tunnel = 0.0f;  // radius of a hole through the sphere along z (0: whole)
  Scene() {
    occ.res = 8;
    occ.bits.assign(occ_word_count(occ.res), ~0u);
  }
  DensityAt density() const {
    return [this](const std::vector<Vec3f>& q, std::vector<float>& sigma) {
      sigma.resize(q.size());
      for (size_t i = 0; i < q.size(); ++i) {
        Vec3f p;
        for (int a = 0; a < 3; ++a) p[a] = box.min[a] + q[i][a] * box.extent(a);
        const float r2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
        const bool hole = p[0] * p[0] + p[1] * p[1] < tunnel * tunnel;
        sigma[i] = r2 < kRadius * kRadius && !hole ? kSigma : 0.0f;
      }
    };
  }
};

// Points on the sphere within `deg` of +z (rings of 24 and the pole).
SolidHull face_cap(float deg) {
  SolidHull h;
  h.name = "face";
  h.points.push_back({0.0f, 0.0f, kRadius});
  for (float t = 10.0f; t <= deg + 1e-3f; t += 10.0f)
    for (int k = 0; k < 24; ++k) {
      const float th = t * float(M_PI) / 180.0f, ph = 2.0f * float(M_PI) * k / 24.0f;
      h.points.push_back({kRadius * std::sin(th) * std::cos(ph), kRadius * std::sin(th) * std::sin(ph),
                          kRadius * std::cos(th)});
    }
  return h;
}

HoleReport measure(const Scene& s, const std::vector<Camera>& cams, uint32_t rays_across = 256) {
  HoleCheckOptions o;
  o.rays_across = rays_across;
  return measure_holes(cams, s.box, {}, kStep, s.occ, s.density(), {face_cap(50.0f)}, o);
}

TEST(SubjectHoles, WholeSphereHasNoHoles) {
  Scene s;
  std::vector<Camera> cams;
  for (float yaw : {-40.0f, -15.0f, 0.0f, 20.0f, 35.0f}) {  // within the cap's 50 deg
    const float a = yaw * float(M_PI) / 180.0f;
    cams.push_back(nerftest::look_at_camera(3.0f * std::sin(a), 0.4f, 3.0f * std::cos(a), 96, 40.0f));
  }
  const HoleReport r = measure(s, cams, 96);
  EXPECT_TRUE(r.checked);
  EXPECT_EQ(r.views, cams.size());
  EXPECT_GT(r.rays, 1000u);
  EXPECT_EQ(r.holes, 0.0);
  EXPECT_FALSE(r.broken());
  EXPECT_EQ(r.advice(), "");
}

TEST(SubjectHoles, PunchedHoleIsCaughtWithItsArea) {
  Scene s;
  s.tunnel = 0.08f;
  const std::vector<Camera> front = {nerftest::look_at_camera(0.0f, 0.0f, 40.0f, 256, 1.5f)};
  const HoleReport r = measure(s, front);
  ASSERT_TRUE(r.checked);
  const double hull = kHullShrink * kRadius * std::sin(50.0 * M_PI / 180.0);
  const double expected = double(s.tunnel * s.tunnel) / (hull * hull);  // 0.035
  EXPECT_NEAR(r.holes, expected, 0.1 * expected);
  EXPECT_NEAR(r.worst_view, r.holes, 1e-12);
  EXPECT_TRUE(r.broken());
  ASSERT_EQ(r.where.size(), 1u);
  EXPECT_NE(r.where[0].find("face"), std::string::npos);
  EXPECT_NE(r.advice().find("holes"), std::string::npos);
  EXPECT_NE(r.advice().find("wall"), std::string::npos);
  // A hole smaller than the threshold's area passes: 0.5 % of the hull.
  s.tunnel = float(std::sqrt(0.005) * hull);
  const HoleReport small = measure(s, front);
  EXPECT_GT(small.holes, 0.0);
  EXPECT_LT(small.holes, kSubjectHoleShare);
  EXPECT_FALSE(small.broken());
}

TEST(SubjectHoles, ViewsBehindTheFaceAreNotJudged) {
  Scene s;
  s.tunnel = 0.2f;
  const std::vector<Camera> back = {nerftest::look_at_camera(0.0f, 0.0f, -3.0f, 96, 40.0f)};
  const HoleReport r = measure(s, back);
  EXPECT_FALSE(r.checked);
  EXPECT_FALSE(r.broken());
  EXPECT_NE(r.summary().find("not checked"), std::string::npos);
}

// A convex solid inside the subject (an convex_part_hull of a ball of half the sphere's radius) is
// judged over its whole projection from any side: seen from the side (+x), where the face cap is not
// judged, the tunnel along z is missed by every ray (it runs across the view), and seen from the
// front the share of hole rays is the tunnel's cross-section over the ball's (unshrunk) outline. The
// figure is the worst region's share: the cap's whole rays do not dilute the ball's hole.
TEST(SubjectHoles, ConvexSolidIsJudgedFromAnySideWithoutShrink) {
  Scene s;
  OrientedShape ball;
  ball.kind = OrientedShape::Kind::Ellipsoid;
  ball.half = {0.5f * kRadius, 0.5f * kRadius, 0.5f * kRadius};
  const SolidHull inner = convex_part_hull(ball, "ball", 12, 48);
  EXPECT_TRUE(inner.convex_solid);
  HoleCheckOptions o;
  o.rays_across = 256;
  const std::vector<Camera> side = {nerftest::look_at_camera(40.0f, 0.0f, 0.0f, 256, 1.5f)};
  s.tunnel = 0.05f;
  HoleReport r = measure_holes(side, s.box, {}, kStep, s.occ, s.density(), {face_cap(50.0f), inner}, o);
  ASSERT_TRUE(r.checked);
  ASSERT_EQ(r.regions.size(), 2u);
  EXPECT_EQ(r.regions[0].rays, 0u);  // the face cap faces away from this view
  EXPECT_GT(r.regions[1].rays, 1000u);
  EXPECT_EQ(r.holes, 0.0) << r.summary();
  const std::vector<Camera> front = {nerftest::look_at_camera(0.0f, 0.0f, 40.0f, 256, 1.5f)};
  r = measure_holes(front, s.box, {}, kStep, s.occ, s.density(), {face_cap(50.0f), inner}, o);
  const double expected = double(s.tunnel * s.tunnel) / double(ball.half[0] * ball.half[0]);  // 0.04
  EXPECT_NEAR(r.regions[1].share(), expected, 0.1 * expected) << r.summary();
  EXPECT_NEAR(r.holes, r.regions[1].share(), 1e-12);
  EXPECT_GT(r.holes, r.regions[0].share());
  EXPECT_EQ(r.worst_region(), "ball");
  EXPECT_NE(r.advice().find("of the ball"), std::string::npos) << r.advice();
}

}  // namespace
}  // namespace lorgnette::nerf
