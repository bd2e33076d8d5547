// The subject volume's geometry and occupancy mask (host/nerf/subject_volume.h) against analytic
// shapes: a rotated box and a rotated ellipsoid, written here independently as quadratic forms on
// rotation matrices built from Euler angles. Every cell whose centre lies in the shape must be
// allowed; every cell farther outside than its half diagonal must not (for the ellipsoid: outside
// the ellipsoid scaled by 1 + half diagonal / shortest semi-axis, which holds that neighbourhood);
// and the allowed volume lies between the shape's and that grown shape's.
#include "host/nerf/subject_volume.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lorgnette::nerf {
namespace {

using Mat3 = std::array<Vec3f, 3>;

// Rows: the rotated frame's axes in scene coordinates (R = Rz(c) Ry(b) Rx(a), rows of R^T).
Mat3 rotation_rows(double a, double b, double c) {
  const double ca = std::cos(a), sa = std::sin(a), cb = std::cos(b), sb = std::sin(b), cc = std::cos(c),
               sc = std::sin(c);
  const double R[3][3] = {{cc * cb, cc * sb * sa - sc * ca, cc * sb * ca + sc * sa},
                          {sc * cb, sc * sb * sa + cc * ca, sc * sb * ca - cc * sa},
                          {-sb, cb * sa, cb * ca}};
  Mat3 rows;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) rows[i][j] = float(R[j][i]);  // column i of R
  return rows;
}

// Local coordinates of p, computed in double (independent of OrientedShape::local).
std::array<double, 3> local(const Vec3f& p, const Vec3f& c, const Mat3& rows) {
  std::array<double, 3> q{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) q[i] += double(rows[i][j]) * (double(p[j]) - double(c[j]));
  return q;
}

struct Counts {
  int inside = 0, far_outside = 0, allowed = 0;
};

// Checks the mask of `shape` over `box` against the analytic inside test `in(local, grow)`, where
// grow scales the shape (1 = the shape itself).
template <typename Inside>
Counts check_mask(const OrientedShape& shape, const Aabb& box, uint32_t res, Inside in) {
  SubjectVolume v;
  v.parts.push_back(shape);
  std::vector<uint32_t> mask = volume_occupancy_mask(v, box, res);
  EXPECT_EQ(mask.size(), size_t((res * res * res + 31) / 32));
  double half_diag = 0.0;
  for (int a = 0; a < 3; ++a) half_diag += std::pow(0.5 * box.extent(a) / res, 2);
  half_diag = std::sqrt(half_diag);
  const double shortest = std::min({shape.half[0], shape.half[1], shape.half[2]});
  const double grow = 1.0 + half_diag / shortest;
  Counts n;
  for (uint32_t z = 0; z < res; ++z)
    for (uint32_t y = 0; y < res; ++y)
      for (uint32_t x = 0; x < res; ++x) {
        const uint32_t cell = x + res * (y + res * z), q[3] = {x, y, z};
        Vec3f p;
        for (int a = 0; a < 3; ++a) p[a] = box.min[a] + (float(q[a]) + 0.5f) / float(res) * box.extent(a);
        const bool allowed = (mask[cell >> 5] >> (cell & 31u)) & 1u;
        const auto l = local(p, shape.center, shape.axes);
        n.allowed += allowed;
        if (in(l, 1.0)) {
          ++n.inside;
          EXPECT_TRUE(allowed) << "cell " << x << "," << y << "," << z << " has its centre inside";
        } else if (!in(l, grow)) {
          ++n.far_outside;
          EXPECT_FALSE(allowed) << "cell " << x << "," << y << "," << z << " lies wholly outside";
        }
      }
  EXPECT_EQ(mask_count(mask), uint64_t(n.allowed));
  return n;
}

// A shape of `kind` at `center`, turned by rotation_rows(a, b, c), with half sizes `half`.
OrientedShape shape(OrientedShape::Kind kind, const Vec3f& center, double a, double b, double c,
                    const Vec3f& half) {
  OrientedShape s;
  s.kind = kind;
  s.center = center;
  s.axes = rotation_rows(a, b, c);
  s.half = half;
  return s;
}

// The scene point at `u` in the shape's own units (each coordinate times its half size, along its axes).
Vec3f point_at(const OrientedShape& s, const std::array<double, 3>& u) {
  Vec3f p = s.center;
  for (int a = 0; a < 3; ++a)
    for (int k = 0; k < 3; ++k) p[k] += float(u[a] * s.half[a] * s.axes[a][k]);
  return p;
}

TEST(SubjectVolume, RotatedBoxMask) {
  const OrientedShape s =
      shape(OrientedShape::Kind::Box, {0.1f, -0.2f, 0.05f}, 0.4, -0.7, 1.1, {0.5f, 0.3f, 0.2f});
  Aabb box;
  box.min = {-1.0f, -1.0f, -1.0f}, box.max = {1.0f, 1.0f, 1.0f};
  auto in = [&](const std::array<double, 3>& l, double g) {
    // A box grown by a factor's worth of its shortest side keeps every point within that distance.
    const double d = (g - 1.0) * 0.2;
    return std::fabs(l[0]) <= 0.5 + d && std::fabs(l[1]) <= 0.3 + d && std::fabs(l[2]) <= 0.2 + d;
  };
  Counts n = check_mask(s, box, 48, in);
  // Volume 0.24 of the box's 8 at 48^3: ~3318 cells inside; the grown box bounds the allowed ones.
  EXPECT_GT(n.inside, 2500);
  EXPECT_GT(n.far_outside, 90000);
  const double cell = std::pow(2.0 / 48.0, 3), d = std::sqrt(3.0) / 48.0;
  EXPECT_GE(n.allowed * cell, 0.24);
  EXPECT_LE(n.allowed * cell, 8.0 * (0.5 + d) * (0.3 + d) * (0.2 + d));
  // contains() agrees with the analytic test on points just inside and outside each face.
  for (int a = 0; a < 3; ++a)
    for (double sign : {-1.0, 1.0})
      for (double f : {0.98, 1.02}) {
        std::array<double, 3> u{};
        u[size_t(a)] = sign * f;
        EXPECT_EQ(s.contains(point_at(s, u)), f < 1.0) << "axis " << a << " sign " << sign << " factor " << f;
      }
}

TEST(SubjectVolume, RotatedEllipsoidMask) {
  const OrientedShape s =
      shape(OrientedShape::Kind::Ellipsoid, {-0.15f, 0.1f, 0.2f}, -0.3, 0.5, 2.0, {0.7f, 0.45f, 0.3f});
  Aabb box;  // not a cube: cells are not cubes either
  box.min = {-1.0f, -0.8f, -0.6f}, box.max = {1.0f, 0.9f, 1.0f};
  auto in = [&](const std::array<double, 3>& l, double g) {
    double r = 0.0;
    for (int a = 0; a < 3; ++a) r += std::pow(l[a] / (g * s.half[a]), 2);
    return r <= 1.0;
  };
  const uint32_t res = 40;
  Counts n = check_mask(s, box, res, in);
  const double volume = 4.0 / 3.0 * M_PI * 0.7 * 0.45 * 0.3;
  const double cell = double(box.extent(0)) * box.extent(1) * box.extent(2) / double(res * res * res);
  double half_diag =
      0.5 * std::sqrt(std::pow(2.0 / res, 2) + std::pow(1.7 / res, 2) + std::pow(1.6 / res, 2));
  const double g = 1.0 + half_diag / 0.3;
  EXPECT_GT(n.inside, 0.9 * volume / cell);
  EXPECT_GE(n.allowed * cell, volume);
  EXPECT_LE(n.allowed * cell, volume * g * g * g);
  EXPECT_GT(n.far_outside, 40000);
}

// A cylinder along its second axis: round across it, flat at its ends, with the mask bounded as the
// ellipsoid's is; its hull's points lie on its two end ellipses.
TEST(SubjectVolume, RotatedCylinderMaskAndHull) {
  const OrientedShape s =
      shape(OrientedShape::Kind::Cylinder, {0.1f, -0.1f, 0.05f}, 0.6, -0.4, 0.9, {0.3f, 0.5f, 0.25f});
  Aabb box;
  box.min = {-1.0f, -1.0f, -1.0f}, box.max = {1.0f, 1.0f, 1.0f};
  auto in = [&](const std::array<double, 3>& l, double g) {
    const double d = (g - 1.0) * 0.25;
    return std::fabs(l[1]) <= 0.5 + d &&
           std::pow(l[0] / (0.3 + d), 2) + std::pow(l[2] / (0.25 + d), 2) <= 1.0;
  };
  const uint32_t res = 40;
  Counts n = check_mask(s, box, res, in);
  const double volume = M_PI * 0.3 * 0.25 * 1.0, cell = std::pow(2.0 / res, 3);
  EXPECT_GT(n.inside, 0.9 * volume / cell);
  EXPECT_GE(n.allowed * cell, volume);
  const double d = 2.0 * std::sqrt(3.0) / res;  // an allowed cell lies within its diagonal of the shape
  EXPECT_LE(n.allowed * cell, M_PI * (0.3 + d) * (0.25 + d) * (1.0 + 2.0 * d));
  // Points along the axis beyond an end, and beside it at mid height, are out; the end's rim is in.
  auto at = [&](double x, double y, double z) { return point_at(s, {x, y, z}); };
  EXPECT_TRUE(s.contains(at(0.0, 0.98, 0.0)));
  EXPECT_FALSE(s.contains(at(0.0, 1.02, 0.0)));
  EXPECT_TRUE(
      s.contains(at(0.69, -0.97, 0.69)));  // 0.976 of the radius, at an end: a corner an ellipsoid lacks
  EXPECT_FALSE(s.contains(at(0.73, 0.0, 0.73)));
  const SolidHull h = convex_part_hull(s, "neck");
  EXPECT_TRUE(h.convex_solid);
  ASSERT_EQ(h.points.size(), 32u);
  for (const Vec3f& p : h.points) {
    const Vec3f q = s.local(p);
    EXPECT_NEAR(std::fabs(q[1]), s.half[1], 1e-5);
    EXPECT_NEAR(std::pow(q[0] / s.half[0], 2) + std::pow(q[2] / s.half[2], 2), 1.0, 1e-4);
  }
}

TEST(SubjectVolume, UnionClipAndGrowth) {
  // Two spheres side by side, clipped to a slab: points in either sphere and in the slab are in.
  SubjectVolume v;
  OrientedShape a, b, slab;
  a.kind = b.kind = OrientedShape::Kind::Ellipsoid;
  a.center = {-0.5f, 0.0f, 0.0f}, b.center = {0.5f, 0.0f, 0.0f};
  a.half = b.half = {0.4f, 0.4f, 0.4f};
  slab.center = {0.0f, 0.0f, 0.0f}, slab.half = {2.0f, 0.2f, 2.0f};
  v.parts = {a, b};
  v.clip = slab;
  EXPECT_TRUE(v.contains({-0.5f, 0.1f, 0.0f}));
  EXPECT_TRUE(v.contains({0.8f, -0.15f, 0.0f}));
  EXPECT_FALSE(v.contains({0.0f, 0.0f, 0.0f}));   // between the spheres
  EXPECT_FALSE(v.contains({-0.5f, 0.3f, 0.0f}));  // in a sphere, outside the slab
  SubjectVolume g = v.grown(0.15f);
  EXPECT_TRUE(g.contains({0.0f, 0.0f, 0.0f}));   // the spheres now reach 0.55 from their centres
  EXPECT_TRUE(g.contains({-0.5f, 0.3f, 0.0f}));  // the slab now reaches 0.35
  EXPECT_TRUE(SubjectVolume{}.empty());
  EXPECT_FALSE(SubjectVolume{}.contains({0.0f, 0.0f, 0.0f}));
}

// The room model's cutout around a subject's volume: the volume grown by the margin is cut out, except
// where `body` (what lies right below the volume) holds it. A box volume over the middle of the room
// with the body below its bottom: the cells in the margin beside and above the box are cut out, the
// cells in the margin right below it are the room's, and without the body they were cut out too.
TEST(SubjectVolume, RoomCutoutLeavesWhatLiesBelowToTheRoom) {
  Aabb room;
  for (int a = 0; a < 3; ++a) room.min[a] = -1.0f, room.max[a] = 1.0f;
  const uint32_t res = 40;  // 0.05 per cell
  SubjectVolume v, body;
  OrientedShape box, below;
  box.half = {0.3f, 0.3f, 0.3f};
  v.parts = {box};
  below.center = {0.0f, -1.3f, 0.0f}, below.half = {2.0f, 1.0f, 2.0f};  // y from -0.3 down
  body.parts = {below};
  const float margin = 0.2f;
  const std::vector<uint32_t> with = room_cutout_mask(room, v, margin, body, res),
                              without = room_cutout_mask(room, v, margin, SubjectVolume{}, res);
  auto allowed = [&](const std::vector<uint32_t>& m, float x, float y, float z) {
    const float p[3] = {x, y, z};
    uint32_t idx[3];
    for (int a = 0; a < 3; ++a) idx[a] = uint32_t((p[a] - room.min[a]) / room.extent(a) * float(res));
    const uint32_t c = idx[0] + res * (idx[1] + res * idx[2]);
    return ((m[c >> 5] >> (c & 31u)) & 1u) != 0u;
  };
  for (const auto* m : {&with, &without}) {
    EXPECT_FALSE(allowed(*m, 0.0f, 0.0f, 0.0f));   // the volume
    EXPECT_FALSE(allowed(*m, 0.42f, 0.0f, 0.0f));  // the margin beside it
    EXPECT_FALSE(allowed(*m, 0.0f, 0.42f, 0.0f));  // and above it
    EXPECT_TRUE(allowed(*m, 0.0f, 0.0f, 0.62f));   // beyond the margin
    EXPECT_TRUE(allowed(*m, 0.0f, -0.62f, 0.0f));
  }
  EXPECT_TRUE(allowed(with, 0.0f, -0.32f, 0.0f));  // the margin right below: the room's
  EXPECT_TRUE(allowed(with, 0.42f, -0.42f, 0.0f));
  EXPECT_FALSE(allowed(without, 0.0f, -0.32f, 0.0f));
  EXPECT_FALSE(allowed(without, 0.42f, -0.42f, 0.0f));
  EXPECT_GT(mask_count(with), mask_count(without));
}

// A part that starts part-way up its second axis (y_from): a rotated ellipsoid cut at 0.3 of its
// half height holds the points of the whole one whose local y is at or above that plane, and nothing
// below it, on both sides of the plane; growing keeps the cut where it is relative to the half size.
TEST(SubjectVolume, PartFromAPlaneAcrossItsSecondAxis) {
  const OrientedShape whole =
      shape(OrientedShape::Kind::Ellipsoid, {0.1f, -0.2f, 0.3f}, 0.4, -0.2, 0.7, {0.5f, 0.6f, 0.4f});
  OrientedShape cut = whole;
  cut.y_from = 0.3f;
  int above = 0, below = 0;
  for (double x = -0.55; x <= 0.55; x += 0.05)
    for (double y = -0.65; y <= 0.65; y += 0.05)
      for (double z = -0.45; z <= 0.45; z += 0.05) {
        Vec3f p = whole.center;  // local (x, y, z) in scene coordinates
        for (int k = 0; k < 3; ++k)
          p[k] += float(x * whole.axes[0][k] + y * whole.axes[1][k] + z * whole.axes[2][k]);
        const float ly = whole.local(p)[1];
        if (std::fabs(ly - 0.3f * whole.half[1]) < 1e-4f) continue;  // on the plane: rounding decides
        EXPECT_EQ(cut.contains(p), whole.contains(p) && ly >= 0.3f * whole.half[1])
            << x << " " << y << " " << z;
        if (whole.contains(p)) (ly >= 0.3f * whole.half[1] ? above : below) += 1;
      }
  EXPECT_GT(above, 100);
  EXPECT_GT(below, 1000);
  const OrientedShape g = cut.grown(0.1f);
  EXPECT_FLOAT_EQ(g.y_from, 0.3f);
  EXPECT_FALSE(g.contains(whole.center));  // the centre lies below the cut
  EXPECT_TRUE(whole.contains(whole.center));
}

}  // namespace
}  // namespace lorgnette::nerf
