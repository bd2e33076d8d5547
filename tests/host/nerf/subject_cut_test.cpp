// The seen opacity split by zone (host/nerf/subject_cut.h) against an analytic scene: an opaque sphere
// seen by cameras on a ring. Its visible cap above a height is a known share of what the views see
// (ray-sphere intersections, computed here independently); a zone behind the sphere is hidden and
// gets nothing; unoccupied cells are skipped; and the cut report's advice follows where the cut is.
#include "host/nerf/subject_cut.h"

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
  std::vector<Camera> cameras;
  Scene() {
    occ.res = 8;
    occ.bits.assign(occ_word_count(occ.res), ~0u);
    for (int k = 0; k < 6; ++k) {
      const float a = 0.6f * float(k), h = 0.3f * float(k % 3) - 0.3f;
      cameras.push_back(nerftest::look_at_camera(3.0f * std::sin(a), h, 3.0f * std::cos(a), 48, 40.0f));
    }
  }
  // The sphere's density at model-normalised points.
  DensityAt density() const {
    return [this](const std::vector<Vec3f>& q, std::vector<float>& sigma) {
      sigma.resize(q.size());
      for (size_t i = 0; i < q.size(); ++i) {
        float r2 = 0.0f;
        for (int a = 0; a < 3; ++a) {
          const float p = box.min[a] + q[i][a] * box.extent(a);
          r2 += p * p;
        }
        sigma[i] = r2 < kRadius * kRadius ? kSigma : 0.0f;
      }
    };
  }
};

// Rays (every 4th pixel) that hit the sphere, those whose first hit lies above `y`, and of those the
// ones whose hit lies at x > 0.2.
void count_hits(const std::vector<Camera>& cameras, float y, int* hits, int* above, int* above_x) {
  *hits = *above = *above_x = 0;
  for (const Camera& cam : cameras)
    for (uint32_t py = 0; py < cam.height / 4; ++py)
      for (uint32_t px = 0; px < cam.width / 4; ++px) {
        const LgnVec3 o = camera_origin(&cam), d = camera_ray_dir(&cam, (px + 0.5f) * 4, (py + 0.5f) * 4);
        const double b = double(o.x) * d.x + double(o.y) * d.y + double(o.z) * d.z;
        const double c = double(o.x) * o.x + double(o.y) * o.y + double(o.z) * o.z - kRadius * kRadius;
        const double disc = b * b - c;
        if (disc < 0.0) continue;
        // Grazing rays cross less than a few steps of the sphere and count partly; leave them out of
        // both sides (the tolerance below covers them).
        if (std::sqrt(disc) < 4.0 * kStep) continue;
        const double t = -b - std::sqrt(disc);
        ++*hits;
        const bool up = o.y + t * d.y > y;
        *above += up;
        *above_x += up && o.x + t * d.x > 0.2;
      }
}

TEST(SubjectCut, SeenShareOfAVisibleCapMatchesTheIntersections) {
  const Scene s;
  const float y = 0.2f;
  // The zone: a shell 0.05 deep under the sphere's surface, above y (the rim of a volume cut there).
  // Zone 2: the same cap's part at x > 0.2.
  auto cap = [&](const Vec3f& p) {
    const float r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    if (!(p[1] > y && r > kRadius - 0.05f)) return 0;
    return p[0] > 0.2f ? 2 : 1;
  };
  const SeenOpacity seen = seen_opacity(s.cameras, s.box, {}, kStep, s.occ, 4, s.density(), 2, cap);
  int hits = 0, above = 0, above_x = 0;
  count_hits(s.cameras, y, &hits, &above, &above_x);
  ASSERT_GT(hits, 100);
  ASSERT_GT(above, 10);
  EXPECT_EQ(seen.rays, s.cameras.size() * 12 * 12);
  // Every ray that hits the sphere is opaque (400 x 0.004 = 1.6 optical depth per step) within the
  // shell, so the seen opacity is the hit count, and the cap's share is the share of hits above y.
  EXPECT_NEAR(seen.total, double(hits), 0.05 * hits);
  EXPECT_NEAR(seen.share(1), double(above - above_x) / double(hits), 0.02);
  EXPECT_NEAR(seen.share(2), double(above_x) / double(hits), 0.02);
  EXPECT_GT(above_x, 5);
}

TEST(SubjectCut, HiddenZoneAndEmptyCellsSeeNothing) {
  Scene s;
  // The sphere's far half from a single camera on +z: hidden behind its near half.
  const std::vector<Camera> front = {nerftest::look_at_camera(0.0f, 0.0f, 3.0f, 48, 40.0f)};
  auto back = [](const Vec3f& p) { return p[2] < -0.05f ? 1 : 0; };
  const SeenOpacity hidden = seen_opacity(front, s.box, {}, kStep, s.occ, 4, s.density(), 1, back);
  EXPECT_GT(hidden.total, 10.0);
  EXPECT_LT(hidden.share(1), 1e-3);
  // With every cell empty nothing is marched.
  s.occ.bits.assign(s.occ.bits.size(), 0u);
  const SeenOpacity none = seen_opacity(front, s.box, {}, kStep, s.occ, 4, s.density(), 1, back);
  EXPECT_EQ(none.total, 0.0);
  EXPECT_EQ(none.share(1), 0.0);
}

// The advice says where the cut lies and names the remedy, --hair, for the top and back and for the
// sides alike (it widens the sides by half as much as it raises the top).
TEST(SubjectCut, AdviceFollowsWhereTheCutIs) {
  SubjectCutReport r;
  EXPECT_FALSE(r.cut());
  EXPECT_EQ(r.advice(), "");
  r.checked = true;
  r.rim_share = r.sides_share = 0.5 * kSubjectCutShare;
  EXPECT_FALSE(r.cut());
  EXPECT_EQ(r.advice(), "");
  r.rim_share = 2.0 * kSubjectCutShare;
  EXPECT_TRUE(r.cut());
  EXPECT_NE(r.advice().find("--hair 100"), std::string::npos);
  EXPECT_NE(r.advice().find("above or behind"), std::string::npos);
  EXPECT_EQ(r.advice().find("at its sides"), std::string::npos);
  r.rim_share = 0.0, r.sides_share = 2.0 * kSubjectCutShare;
  EXPECT_TRUE(r.cut());
  EXPECT_NE(r.advice().find("--hair 100"), std::string::npos);
  EXPECT_EQ(r.advice().find("above or behind"), std::string::npos);
  EXPECT_NE(r.advice().find("at its sides"), std::string::npos);
  r.rim_share = 2.0 * kSubjectCutShare;
  EXPECT_NE(r.advice().find("behind the head (0.20 %"), std::string::npos);
  EXPECT_NE(r.advice().find(" and at its sides above the ears (0.20 %)"), std::string::npos);
}

}  // namespace
}  // namespace lorgnette::nerf
