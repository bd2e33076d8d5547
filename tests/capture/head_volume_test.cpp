// The head volume (capture/head_volume.h) keeps the head and drops the box's corners: every vertex
// of procedural heads with neck and shoulders (random shapes, seeds 0-5) that lies in the oriented
// head box is inside the head volume, with the head upright and tilted in the scene; the 68 points
// of the mean face are inside with a 10 mm margin; and the volume's occupancy mask over the box's
// axis-aligned bounds leaves out the corners that the tilt adds (where a wall close behind the subject
// is rebuilt: docs/room-training.md, "The head's volume").
#include "capture/head_volume.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "fit/landmark_ids.h"
#include "fit/mean_face.h"
#include "synth/subject.h"

namespace lorgnette::capture {
namespace {

nerf::Vec3f vec(const Eigen::Vector3d& p) { return {float(p.x()), float(p.y()), float(p.z())}; }

// The head box of a procedural subject from its true head frame (rotated by `rot` in the scene),
// anchored as fit::estimate_head_box anchors it (the eye corners' centroid, at the inner corners'
// depth), and the subject's vertices in that scene.
struct PlacedHead {
  fit::HeadBox box;
  std::vector<Eigen::Vector3d> vertices;
};

PlacedHead place(const synth::Subject& s, const Eigen::Matrix3d& rot) {
  const double mpu = *s.mm_per_unit;
  auto scene = [&](const Eigen::Vector3f& dataset_point) {
    return Eigen::Vector3d(rot * dataset_point.cast<double>());
  };
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int k : {fit::lm::kEyeOuterR, fit::lm::kEyeInnerR, fit::lm::kEyeInnerL, fit::lm::kEyeOuterL})
    centroid += 0.25 * scene(s.ibug68[k]);
  const Eigen::Vector3d inner =
      0.5 * (scene(s.ibug68[fit::lm::kEyeInnerR]) + scene(s.ibug68[fit::lm::kEyeInnerL]));
  fit::HeadFrame head;
  head.d_eye = rot.col(0), head.d_up = rot.col(1), head.d_fwd = rot.col(2);
  head.mm_per_unit = mpu;
  const Eigen::Vector3d anchor = centroid + head.d_fwd * head.d_fwd.dot(inner - centroid);
  PlacedHead out{fit::head_box_from_frame(head, anchor, fit::HeadExtents{}), {}};
  for (const auto& v : s.mesh.positions)
    out.vertices.push_back(scene(synth::transform_point(s.mesh_to_dataset, v)));
  return out;
}

// Vertices in the oriented box but outside the head volume.
int cut_vertices(const PlacedHead& h, int* in_box) {
  nerf::SubjectVolume box = head_volume(h.box, HeadVolumeShape::OrientedBox), vol = head_volume(h.box);
  int cut = 0;
  *in_box = 0;
  for (const auto& v : h.vertices) {
    if (!box.contains(vec(v))) continue;
    ++*in_box;
    cut += !vol.contains(vec(v));
  }
  return cut;
}

TEST(HeadVolume, KeepsProceduralHeadsUprightAndTilted) {
  const Eigen::Matrix3d tilt =
      (Eigen::AngleAxisd(0.45, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(-0.3, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()))
          .toRotationMatrix();
  for (int seed = 0; seed < 6; ++seed) {
    synth::Subject s =
        synth::procedural_subject(synth::random_head_params(seed), synth::HeadMeshOptions{96, 48, 256}, true);
    for (const Eigen::Matrix3d& rot : {Eigen::Matrix3d(Eigen::Matrix3d::Identity()), tilt}) {
      int in_box = 0;
      EXPECT_EQ(cut_vertices(place(s, rot), &in_box), 0) << "seed " << seed;
      EXPECT_GT(in_box, 1000) << "seed " << seed;
    }
  }
}

TEST(HeadVolume, MeanFaceInsideWithMargin) {
  nerf::SubjectVolume vol = head_volume_mm(fit::HeadExtents{});
  const fit::Face68& face = fit::builtin_mean_face();
  ASSERT_EQ(face.size(), 68u);
  // The mean face is in mm about its own origin; move it so its eye anchor is the volume's origin.
  const Eigen::Vector3d anchor = fit::face_anchor(face);
  for (int k = 0; k < 68; ++k)
    for (int a = 0; a < 3; ++a)
      for (double d : {-10.0, 10.0}) {
        Eigen::Vector3d p = face[k] - anchor;
        p[a] += d;
        EXPECT_TRUE(vol.contains(vec(p))) << "landmark " << k << " moved " << d << " mm along axis " << a;
      }
}

TEST(HeadVolume, MaskDropsTheTiltedBoxCorners) {
  // A head pitched 25 deg (as fangzhou-frontal's is in its scene): the axis-aligned box gains
  // corners; the oriented box's mask drops them, the head volume drops more and keeps the head.
  synth::Subject s =
      synth::procedural_subject(synth::random_head_params(0), synth::HeadMeshOptions{96, 48, 256}, true);
  PlacedHead h = place(s, Eigen::AngleAxisd(0.44, Eigen::Vector3d::UnitX()).toRotationMatrix());
  nerf::Aabb aabb;
  for (int a = 0; a < 3; ++a) aabb.min[a] = float(h.box.min[a]), aabb.max[a] = float(h.box.max[a]);
  const uint32_t res = 64;
  const double cells = double(res) * res * res;
  nerf::SubjectVolume box = head_volume(h.box, HeadVolumeShape::OrientedBox), vol = head_volume(h.box);
  const double box_share = double(nerf::mask_count(nerf::volume_occupancy_mask(box, aabb, res))) / cells;
  const double vol_share = double(nerf::mask_count(nerf::volume_occupancy_mask(vol, aabb, res))) / cells;
  // Oriented box / its bounds at 25 deg about x: (y z) / ((y cos + z sin)(y sin + z cos)) with the
  // box's 340 x 284 mm side: 96560 / (428 x 401) = 0.56, plus the boundary cells (~+0.05).
  EXPECT_GT(box_share, 0.5);
  EXPECT_LT(box_share, 0.66);
  EXPECT_LT(vol_share, box_share - 0.05);
  std::vector<uint32_t> mask = nerf::volume_occupancy_mask(vol, aabb, res);
  int lost = 0;
  for (const auto& v : h.vertices) {
    int idx[3];
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      double f = (v[a] - aabb.min[a]) / aabb.extent(a);
      inside = inside && f >= 0.0 && f < 1.0;
      idx[a] = std::clamp(int(f * res), 0, int(res) - 1);
    }
    if (!inside || !box.contains(vec(v))) continue;
    uint32_t cell = uint32_t(idx[0]) + res * (uint32_t(idx[1]) + res * uint32_t(idx[2]));
    lost += !((mask[cell >> 5] >> (cell & 31u)) & 1u);
  }
  EXPECT_EQ(lost, 0) << "head vertices in cells the mask drops";
}

// The room-clearing's keep zone is the neck: below the average chin to the box's bottom, as wide as
// the head's p99 breadth; the eyes, nose, mouth and the mean face's chin are above it, and the space
// beside the neck (loose hair, seen against the wall) is outside it.
TEST(HeadVolume, ClearKeepIsTheNeckBelowTheChin) {
  const fit::HeadExtents e;
  const nerf::SubjectVolume keep = head_clear_keep_mm(e);
  auto in = [&](double x, double y, double z) { return keep.contains({float(x), float(y), float(z)}); };
  const double bottom = e.chin_below_eyes_mm + e.neck_mm;
  EXPECT_TRUE(in(0, -bottom + 5, 0));                              // the neck at the box's bottom
  EXPECT_TRUE(in(0, -(e.chin_below_eyes_mm + 5), -80));            // under the p99 chin, behind it
  EXPECT_TRUE(in(0.5 * e.head_breadth_mm - 5, -bottom + 5, 0));    // the neck's widest
  EXPECT_FALSE(in(0.5 * e.head_breadth_mm + 10, -bottom + 5, 0));  // beside the neck
  EXPECT_FALSE(in(-0.5 * e.head_breadth_mm - 10, -(e.chin_below_eyes_mm + 5), -40));
  EXPECT_FALSE(in(0, 0, 0));              // between the eyes
  EXPECT_FALSE(in(0, -114.0 + 5.0, 10));  // just above the mean face's menton
  EXPECT_FALSE(in(0, -bottom - 5, 0));    // below the box: the room's
  // Every mean-face landmark (its eye anchor at the origin, as above) lies above the keep zone.
  const fit::Face68& face = fit::builtin_mean_face();
  const Eigen::Vector3d anchor = fit::face_anchor(face);
  for (int k = 0; k < 68; ++k) {
    const Eigen::Vector3d p = face[k] - anchor;
    EXPECT_FALSE(in(p.x(), p.y(), p.z())) << "landmark " << k;
  }
}

// The clearing's core is the bare head: it holds the mean face (10 mm margin), the ears beside the
// skull and the neck, and leaves out the hair margins behind and above the p99 skull that the head
// volume keeps; the lean zone (the volume outside the core) lies behind the ears or above the brows,
// never beside or in front of the face.
TEST(HeadVolume, ClearCoreIsTheBareHead) {
  const fit::HeadExtents e;
  const nerf::SubjectVolume core = head_clear_core_mm(e), vol = head_volume_mm(e);
  auto in = [](const nerf::SubjectVolume& v, double x, double y, double z) {
    return v.contains({float(x), float(y), float(z)});
  };
  // The mean face about the volumes' anchor.
  const fit::Face68& face = fit::builtin_mean_face();
  const Eigen::Vector3d anchor = fit::face_anchor(face);
  int core_points = 0, lean_points = 0;
  for (double x = -300; x <= 300; x += 10)
    for (double y = -300; y <= 300; y += 10)
      for (double z = -350; z <= 150; z += 10) {
        core_points += in(core, x, y, z);
        if (!in(vol, x, y, z) || in(core, x, y, z)) continue;
        ++lean_points;  // the lean zone keeps 15 mm from every face landmark, jawline included
        double nearest = 1e9;
        for (int k = 0; k < 68; ++k)
          nearest = std::min(nearest, (face[k] - anchor - Eigen::Vector3d(x, y, z)).norm());
        EXPECT_GT(nearest, 15.0) << x << " " << y << " " << z;
      }
  EXPECT_GT(core_points, 5000);  // the bare head is ~ 4 litres: ~4000 points at 1 cm, plus the neck
  EXPECT_GT(lean_points, 1000);  // the hair margins: 30 + 40 mm behind and above a ~20 x 20 cm skull
  const double back = e.head_length_mm - e.glabella_ahead_mm;   // the p99 skull's back
  EXPECT_TRUE(in(core, 0, 0, -back + 10));                      // the back of the skull
  EXPECT_FALSE(in(core, 0, 0, -back - 20));                     // hair behind it
  EXPECT_TRUE(in(vol, 0, 0, -back - 20));                       // which the head volume keeps
  EXPECT_TRUE(in(core, 0, e.vertex_above_eyes_mm - 10, -80));   // the crown
  EXPECT_FALSE(in(core, 0, e.vertex_above_eyes_mm + 20, -80));  // hair on top
  EXPECT_TRUE(in(vol, 0, e.vertex_above_eyes_mm + 20, -80));
  // The ears and the side hair beside them: as wide as the head volume there.
  const double ear_x = 0.5 * e.head_breadth_mm + e.side_margin_mm;
  EXPECT_TRUE(in(core, ear_x, -30, -90));
  EXPECT_EQ(in(core, ear_x + 30, -30, -90), in(vol, ear_x + 30, -30, -90));
  EXPECT_TRUE(in(core, 0, -(e.chin_below_eyes_mm + 20), -90));  // the neck
  for (int k = 0; k < 68; ++k)
    for (int a = 0; a < 3; ++a)
      for (double d : {-10.0, 10.0}) {
        Eigen::Vector3d p = face[k] - anchor;
        p[a] += d;
        EXPECT_TRUE(in(core, p.x(), p.y(), p.z())) << "landmark " << k << " moved " << d << " along " << a;
      }
}

// The nape (under the back of the skull, behind the neck) is in the head volume but in neither
// clearing zone: the keep zone and the core end 0.8 head lengths behind the glabella, the core's skull
// 40 mm below the eyes. In front of it the neck stays in both, and above it the back of the skull
// stays in the core.
TEST(HeadVolume, ClearZonesLeaveOutTheNape) {
  const fit::HeadExtents e;
  const nerf::SubjectVolume vol = head_volume_mm(e), core = head_clear_core_mm(e),
                            keep = head_clear_keep_mm(e);
  auto in = [](const nerf::SubjectVolume& v, double x, double y, double z) {
    return v.contains({float(x), float(y), float(z)});
  };
  const double nape = e.glabella_ahead_mm - 0.8 * e.head_length_mm;  // 156 mm behind the eyes
  const double back = e.head_length_mm - e.glabella_ahead_mm;        // the p99 skull's back, 199 mm
  const double under_chin = -(e.chin_below_eyes_mm + 10);
  for (double y : {-60.0, -90.0, under_chin}) {
    EXPECT_TRUE(in(vol, 0, y, nape - 15)) << y;    // the volume keeps the nape
    EXPECT_FALSE(in(core, 0, y, nape - 15)) << y;  // the core does not hold it
    EXPECT_TRUE(in(core, 0, y, nape + 15)) << y;   // nor the neck in front of it
  }
  EXPECT_FALSE(in(keep, 0, under_chin, nape - 15));
  EXPECT_TRUE(in(keep, 0, under_chin, nape + 15));
  EXPECT_TRUE(in(core, 0, -30, -back + 10));  // the back of the skull above the nape
}

// What lies right below the head box is the room model's (head_room_body): the neck's base under
// the box, in front of and behind it, and the shoulders beside it, as far below as the room's
// cutout margin reaches (~35 mm on the room captures) and further; none of the head volume is.
TEST(HeadVolume, RoomHoldsWhatLiesBelowTheBox) {
  const fit::HeadExtents e;
  const nerf::SubjectVolume vol = head_volume_mm(e), body = head_room_body_mm(e);
  auto in = [](const nerf::SubjectVolume& v, double x, double y, double z) {
    return v.contains({float(x), float(y), float(z)});
  };
  const double bottom = e.chin_below_eyes_mm + e.neck_mm;  // the box's bottom below the eyes
  for (double below : {1.0, 20.0, 60.0}) {
    EXPECT_TRUE(in(body, 0, -bottom - below, -46)) << below;    // the throat
    EXPECT_TRUE(in(body, 0, -bottom - below, -170)) << below;   // the nape
    EXPECT_TRUE(in(body, 150, -bottom - below, -90)) << below;  // a shoulder
    EXPECT_FALSE(in(vol, 0, -bottom - below, -46)) << below;
  }
  // Above the bottom nothing of the head volume is the room's.
  int checked = 0;
  for (double x = -150; x <= 150; x += 10)
    for (double y = -bottom + 1; y <= 200; y += 10)
      for (double z = -280; z <= 80; z += 10)
        if (in(vol, x, y, z)) {
          ++checked;
          EXPECT_FALSE(in(body, x, y, z)) << x << " " << y << " " << z;
        }
  EXPECT_GT(checked, 1000);
}

// `train --hair MM` (a bun, tall hair, a hat): the volume and its clip reach that much further above
// and behind the skull, and from eye level up half the declared hair (beyond the standard 30 mm)
// further sideways; below the eyes and in front of the skull's middle nothing moves. The declared hair
// joins the bare head (the clearing's core), so only the standard margin beyond it leans towards the
// room.
TEST(HeadVolume, HairAllowanceRaisesTheTopAndTheBack) {
  fit::HeadExtents tall;
  tall.hair_mm = 150.0;
  const fit::HeadExtents e;
  const nerf::SubjectVolume vol = head_volume_mm(e), tall_vol = head_volume_mm(tall);
  const nerf::SubjectVolume core = head_clear_core_mm(e), tall_core = head_clear_core_mm(tall);
  auto in = [](const nerf::SubjectVolume& v, double x, double y, double z) {
    return v.contains({float(x), float(y), float(z)});
  };
  const double top = e.vertex_above_eyes_mm, back = e.head_length_mm - e.glabella_ahead_mm;
  // A crown 100 mm above the skull and a bun 100 mm behind it: cut by default, kept with 150 mm, and
  // in the core (120 mm declared beyond the standard 30).
  EXPECT_FALSE(in(vol, 0, top + 100, -80));
  EXPECT_TRUE(in(tall_vol, 0, top + 100, -80));
  EXPECT_TRUE(in(tall_core, 0, top + 100, -80));
  EXPECT_FALSE(in(vol, 0, 20, -back - 100));
  EXPECT_TRUE(in(tall_vol, 0, 20, -back - 100));
  EXPECT_TRUE(in(tall_core, 0, 20, -back - 100));
  // The standard margin beyond the declared hair leans (in the volume, not in the core).
  EXPECT_TRUE(in(tall_vol, 0, top + 160, -150));
  EXPECT_FALSE(in(tall_core, 0, top + 160, -150));
  // Still bounded: 150 mm of hair and the 40 mm of loose hair, not more.
  EXPECT_FALSE(in(tall_vol, 0, top + 200, -80));
  EXPECT_FALSE(in(tall_vol, 0, 20, -back - 200));
  // The sides above the ears: the default volume ends at the box's side and its loose hair; the tall
  // one reaches half the declared 120 mm further, and is in the core there too, and not further.
  const double side = 0.5 * e.head_breadth_mm + e.side_margin_mm + 40.0;  // box side + loose hair
  EXPECT_TRUE(in(vol, side - 5, 40, -90));
  EXPECT_FALSE(in(vol, side + 5, 40, -90));
  // (at the tall skull's mid-depth, where its ellipsoid is widest)
  EXPECT_TRUE(in(tall_vol, side + 50, 40, -170));
  EXPECT_TRUE(in(tall_vol, -(side + 50), 40, -170));
  EXPECT_TRUE(in(tall_core, side + 50, 40, -170));
  EXPECT_FALSE(in(vol, side + 50, 40, -170));
  EXPECT_FALSE(in(tall_vol, side + 70, 40, -170));
  // Below the eyes the sides stay (a frontal capture's room beside the jaw and the neck).
  EXPECT_FALSE(in(tall_vol, side + 20, -20, -170));
  EXPECT_FALSE(in(tall_core, side + 20, -20, -170));
  for (double x = -200; x <= 200; x += 20)
    for (double y = -300; y <= 300; y += 20)
      for (double z = -400; z <= 150; z += 20) {
        if (in(core, x, y, z)) {
          EXPECT_TRUE(in(tall_core, x, y, z)) << x << " " << y << " " << z;
        }
        // More hair only adds; below the eyes and in front of the skull's middle the volume is
        // unchanged.
        if (in(vol, x, y, z)) {
          EXPECT_TRUE(in(tall_vol, x, y, z)) << x << " " << y << " " << z;
        }
        if (y < 0 && z > -100) {
          EXPECT_EQ(in(vol, x, y, z), in(tall_vol, x, y, z)) << x << " " << y << " " << z;
        }
      }
}

// The cut rim (head_cut_rim_mm): the head volume's outer 6 mm from 20 mm above the eyes up, behind the
// eyes, so a crown cut at the volume's top lies in it, while the skull, the hair within the allowance,
// the face, the ears and the neck do not; with `--hair` it follows the larger volume.
TEST(HeadVolume, CutRimIsTheVolumesTopEdge) {
  const fit::HeadExtents e;
  fit::HeadExtents tall;
  tall.hair_mm = 150.0;
  const nerf::SubjectRim rim = head_cut_rim_mm(e), tall_rim = head_cut_rim_mm(tall);
  const nerf::SubjectVolume vol = head_volume_mm(e);
  auto in = [](const nerf::SubjectRim& r, double x, double y, double z) {
    return r.zone({float(x), float(y), float(z)}) != 0;
  };
  // The volume's top above the crown: its last mm are rim; 10 mm further in are not.
  double top = e.vertex_above_eyes_mm;
  while (vol.contains({0.0f, float(top + 1), -80.0f})) top += 1;
  EXPECT_GT(top, e.vertex_above_eyes_mm + e.hair_mm);  // hair and loose hair above the p99 skull
  EXPECT_TRUE(in(rim, 0, top - 2, -80));
  EXPECT_FALSE(in(rim, 0, top - 10, -80));
  EXPECT_FALSE(in(tall_rim, 0, top - 2, -80));  // 150 mm of hair: well inside
  // A p99 head with its 30 mm of hair is not rim: the top and back of the hair, the skull's sides
  // above the brows, the forehead, and the 68 points of the mean face.
  const double back = e.head_length_mm - e.glabella_ahead_mm, half = 0.5 * e.head_breadth_mm;
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(0, e.vertex_above_eyes_mm + e.hair_mm, -80),
        Eigen::Vector3d(0, 40, -back - e.hair_mm), Eigen::Vector3d(half, 40, -90),
        Eigen::Vector3d(-half, 40, -90), Eigen::Vector3d(0, 40, e.glabella_ahead_mm)})
    EXPECT_FALSE(in(rim, p.x(), p.y(), p.z())) << p.transpose();
  const fit::Face68& face = fit::builtin_mean_face();
  const Eigen::Vector3d anchor = fit::face_anchor(face);
  for (int k = 0; k < 68; ++k) {
    const Eigen::Vector3d p = face[k] - anchor;
    EXPECT_FALSE(in(rim, p.x(), p.y(), p.z())) << "landmark " << k;
  }
  // Below the brows the volume's edge is not rim: the side of the head at ear height, the neck's end.
  double side = 0.5 * e.head_breadth_mm;
  while (vol.contains({float(side + 1), -30.0f, -90.0f})) side += 1;
  EXPECT_FALSE(in(rim, side - 2, -30, -90));
  EXPECT_FALSE(in(rim, 0, -(e.chin_below_eyes_mm + e.neck_mm) + 2, -90));
  // Nor is the face box's front above the brows, which frontal captures' foreheads reach.
  double front = 0.0;
  while (vol.contains({0.0f, 40.0f, float(front + 1)})) front += 1;
  EXPECT_GT(front, e.glabella_ahead_mm);
  EXPECT_FALSE(in(rim, 0, 40, front - 2));
  // Its side above the brows is, in the fixed part (beyond the head box's sides); the top is not.
  double upper_side = 0.5 * e.head_breadth_mm;
  while (vol.contains({float(upper_side + 1), 60.0f, -90.0f})) upper_side += 1;
  EXPECT_TRUE(in(rim, upper_side - 2, 60, -90));
  EXPECT_EQ(rim.zone({float(upper_side - 2), 60.0f, -90.0f}), 2);
  EXPECT_EQ(rim.zone({float(-(upper_side - 2)), 60.0f, -90.0f}), 2);
  EXPECT_EQ(rim.zone({0.0f, float(top - 2), -80.0f}), 1);
  EXPECT_EQ(rim.zone({0.0f, 0.0f, -80.0f}), 0);
}

}  // namespace
}  // namespace lorgnette::capture
