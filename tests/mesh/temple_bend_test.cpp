// Temple spread (mesh/temple_bend.h, mesh/placed_glasses.h): points ahead of the hinge and the nose
// pads stay put; points past the ramp turn by exactly the spread about the vertical axis through
// the hinge, outwards; the map is continuous (Lipschitz) across the ramp; normals equal the
// finite-difference normals of the deformed surface; mesh and point paths agree bit for bit; hinges
// are found where a parametric frame's temples join its front; the placement.json codec round-trips;
// and a spread frame's surface pass differs from the rigid one only behind the hinges.
#include "mesh/temple_bend.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <random>

#include "mesh/frame_metrics.h"
#include "mesh/parametric.h"
#include "mesh/placed_glasses.h"

namespace lorgnette::mesh {
namespace {

TempleBend sample_bend(double left_deg = 12.0, double right_deg = 7.0) {
  TempleBend b;
  b.left.hinge = {68.0, 10.0, -2.0};
  b.right.hinge = {-68.0, 10.0, -2.0};
  b.left.spread_deg = left_deg;
  b.right.spread_deg = right_deg;
  b.ramp_mm = 4.0;
  return b;
}

// Angle (degrees) turning the xz projection of a to that of b, about +y.
double angle_about_y(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.z() * b.x() - a.x() * b.z(), a.x() * b.x() + a.z() * b.z()) * 180.0 / M_PI;
}

TEST(TempleBend, AheadOfTheHingeAndNosePadsStayPut) {
  TempleBend b = sample_bend();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> x(-80, 80), y(-30, 30), z(-1.999, 10);
  for (int i = 0; i < 1000; ++i) {
    Eigen::Vector3d p(x(rng), y(rng), z(rng));
    EXPECT_EQ(bend_point(b, p), p);
  }
  // Behind the front but near the symmetry plane (nose pads): rigid.
  for (double px : {-30.0, -8.0, 8.0, 33.9})
    EXPECT_EQ(bend_point(b, Eigen::Vector3d(px, 0, -12)), Eigen::Vector3d(px, 0, -12));
  EXPECT_FALSE(TempleBend{}.active());
}

TEST(TempleBend, FarBehindTurnsByExactlyTheSpreadOutwards) {
  TempleBend b = sample_bend();
  for (int side : {+1, -1}) {
    const TempleSide& t = side > 0 ? b.left : b.right;
    for (double depth : {4.0, 10.0, 60.0, 130.0}) {
      for (double dx : {-6.0, 0.0, 2.0}) {
        Eigen::Vector3d p = t.hinge + Eigen::Vector3d(side * dx, 3.0, -depth);
        Eigen::Vector3d q = bend_point(b, p);
        Eigen::Vector3d r0 = p - t.hinge, r1 = q - t.hinge;
        // A rotation about +y through the hinge: y kept, distance to the axis kept (1e-9 mm: doubles).
        EXPECT_NEAR(q.y(), p.y(), 1e-12);
        EXPECT_NEAR(std::hypot(r1.x(), r1.z()), std::hypot(r0.x(), r0.z()), 1e-9);
        // By exactly the spread; outwards = away from the symmetry plane (left: -angle about +y).
        EXPECT_NEAR(angle_about_y(r0, r1), -side * t.spread_deg, 1e-9);
      }
      EXPECT_GT(
          side * (bend_point(b, Eigen::Vector3d(t.hinge + Eigen::Vector3d(0, 0, -depth))).x() - t.hinge.x()),
          0.0);
    }
  }
}

TEST(TempleBend, ContinuousAcrossTheRamp) {
  // Walk a line from 1 mm ahead of the hinge to 10 mm behind it in 1 um steps: consecutive images
  // must stay within L * step with L = 1 + |spread| * |r| * max|w'| (the twist term's bound; max w' =
  // 1.5 / ramp for smoothstep), r the offset from the hinge axis (<= 12 mm here).
  TempleBend b = sample_bend(20.0, 20.0);
  const double h = 1e-3, lip = 1.0 + (20.0 * M_PI / 180.0) * 12.0 * 1.5 / b.ramp_mm;
  for (double dx : {-3.0, 0.0, 3.0}) {
    Eigen::Vector3d prev = bend_point(b, Eigen::Vector3d(68.0 + dx, 0, -1.0));
    for (double z = -1.0 - h; z > -12.0; z -= h) {
      Eigen::Vector3d q = bend_point(b, Eigen::Vector3d(68.0 + dx, 0, z));
      ASSERT_LE((q - prev).norm(), lip * h * (1 + 1e-9)) << "z " << z;
      prev = q;
    }
  }
  // At the hinge nothing moves; at the ramp's end the full spread applies.
  EXPECT_EQ(bend_point(b, Eigen::Vector3d(70, 0, -2.0)), Eigen::Vector3d(70, 0, -2.0));
  Eigen::Vector3d end(70, 0, -6.0), r = bend_point(b, end) - b.left.hinge;
  EXPECT_NEAR(angle_about_y(end - b.left.hinge, r), -20.0, 1e-9);
}

TEST(TempleBend, NormalsMatchTheDeformedSurface) {
  // A small surface patch at p with tangents t1, t2: the deformed normal must be the normalised
  // cross product of the deformed tangents (central differences, step 1e-5 mm: error ~1e-9).
  TempleBend b = sample_bend(18.0, 9.0);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 200; ++i) {
    int side = i % 2 ? 1 : -1;
    Eigen::Vector3d p(side * (68 + 4 * u(rng)), 10 * u(rng), -2.0 - 3.0 * (u(rng) + 1.0));  // inside the ramp
    if (i % 4 >= 2) p.z() -= 20.0;                                                          // or behind it
    Eigen::Vector3d t1 = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    Eigen::Vector3d t2 = t1.unitOrthogonal();
    const double e = 1e-5;
    auto d = [&](const Eigen::Vector3d& t) -> Eigen::Vector3d {
      return (bend_point(b, Eigen::Vector3d(p + e * t)) - bend_point(b, Eigen::Vector3d(p - e * t))) /
             (2 * e);
    };
    Eigen::Vector3d expect = d(t1).cross(d(t2)).normalized();
    Eigen::Vector3d got = bend_normal(b, p, t1.cross(t2));
    EXPECT_NEAR((got - expect).norm(), 0.0, 1e-6) << p.transpose();
  }
}

TEST(TempleBend, MeshAndPointsAgreeExactly) {
  ParametricFrame f = make_parametric_frame(FrameParams{});
  TempleBend b = sample_bend(9.5, 14.25);
  TriMesh m = f.mesh;
  bend_mesh(b, m);
  ASSERT_EQ(m.positions.size(), f.mesh.positions.size());
  int moved = 0;
  for (size_t i = 0; i < m.positions.size(); ++i) {
    EXPECT_EQ(m.positions[i], bend_point(b, f.mesh.positions[i]));
    std::vector<Eigen::Vector3d> one = bend_points(b, {f.mesh.positions[i].cast<double>()});
    EXPECT_EQ(m.positions[i], one[0].cast<float>());
    moved += m.positions[i] != f.mesh.positions[i];
  }
  EXPECT_GT(moved, 100);
}

TEST(TempleBend, HingesOfAParametricFrame) {
  // The parametric temple leaves the front at the rims' back face, z = 0 (g_c, the canonical origin,
  // is on that face), on the temple's centre line x = g_l.x. Detection bins are 0.5 mm and the hinge
  // is put at the back of the last tall bin: never ahead of the front's back face.
  for (float lens : {48.0f, 56.0f}) {
    FrameParams fp;
    fp.lens_width = lens;
    ParametricFrame f = make_parametric_frame(fp);
    std::string why;
    auto h = detect_temple_hinges(f.mesh, &why);
    ASSERT_TRUE(h) << why;
    EXPECT_LE(h->left.z(), 0.0);
    EXPECT_GE(h->left.z(), -0.5 - 1e-6);
    EXPECT_NEAR(h->left.x(), f.ref.g_l.x(), 1.0);
    EXPECT_EQ(h->right.x(), -h->left.x());
    EXPECT_EQ(h->right.z(), h->left.z());
    // Measuring the frame (every load does) keeps the same hinges for the fit: detected once.
    FrameMetrics m = measure_frame(f.mesh);
    ASSERT_TRUE(m.hinges) << m.no_hinges;
    EXPECT_EQ(m.hinges->left, h->left);
    EXPECT_EQ(m.hinges->right, h->right);
  }
  TriMesh empty;
  std::string why;
  EXPECT_FALSE(detect_temple_hinges(empty, &why));
  EXPECT_FALSE(why.empty());
}

TEST(TempleBend, SurfacePassDiffersOnlyBehindTheHinges) {
  // Seen from above (scene = canonical mm), a spread frame covers other pixels than the rigid one
  // along its temples; every pixel that changed sees (in either image) a point behind the hinges.
  ParametricFrame f = make_parametric_frame(FrameParams{});
  auto hinges = detect_temple_hinges(f.mesh);
  ASSERT_TRUE(hinges);
  TempleBend b;
  b.left.hinge = hinges->left, b.right.hinge = hinges->right;
  b.left.spread_deg = b.right.spread_deg = 10.0;
  Glasses g;
  g.mesh = f.mesh;
  PlacedGlasses rigid = place_glasses_mesh(g, Eigen::Matrix4d::Identity(), {});
  PlacedGlasses spread = place_glasses_mesh(g, Eigen::Matrix4d::Identity(), b);
  Camera cam = look_at_camera({0, 400, -50}, {0, 0, -50}, {0, 0, 1}, 30.0f, 96, 96);
  SurfaceParams sp;
  sp.samples_per_pixel = 4;
  SurfaceBuffers a = rigid.pass->render(cam, sp), c = spread.pass->render(cam, sp);
  int changed = 0;
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 96; ++x) {
      size_t i = size_t(y) * 96 + x;
      // Same geometry, different BVH: Embree's hit distances may differ in the last bits.
      const bool same_depth = a.depth[i] == c.depth[i] || std::abs(a.depth[i] - c.depth[i]) < 1e-3f;
      if (std::abs(a.color_alpha[4 * i + 3] - c.color_alpha[4 * i + 3]) < 1e-4f && same_depth) continue;
      ++changed;
      float t = std::min(a.depth[i], c.depth[i]);  // one of them hit
      ASSERT_TRUE(std::isfinite(t));
      LgnVec3 o = camera_origin(&cam), d = camera_ray_dir(&cam, x + 0.5f, y + 0.5f);
      Eigen::Vector3f hit = Eigen::Vector3f(o.x, o.y, o.z) + t * Eigen::Vector3f(d.x, d.y, d.z);
      EXPECT_LT(hit.z(), hinges->left.z() + 2.5f)
          << x << "," << y << ": depth " << a.depth[i] << " vs " << c.depth[i] << ", alpha "
          << a.color_alpha[4 * i + 3] << " vs " << c.color_alpha[4 * i + 3];  // + a pixel (~2.2 mm)
    }
  EXPECT_GT(changed, 40);
}

}  // namespace
}  // namespace lorgnette::mesh
