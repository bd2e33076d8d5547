// The head's volume in its landmark box; see head_volume.h.
#include "capture/head_volume.h"

#include <algorithm>

namespace lorgnette::capture {
namespace {

using nerf::OrientedShape;

// Hair that stands out beyond the head box's margins (in2n-face's curls reach past the box's sides at
// ear level): the skull part of the volume and the clip reach this much further sideways, upwards
// and backwards. Not forwards, where a frontal capture's wall is otherwise rebuilt beside the face
// (docs/room-training.md, "The head's volume").
constexpr double kLooseHairMm = 40.0;

// The average chin lies about this far above HeadExtents' p99 chin (menton 114 mm below the eyes in
// the mean face, against 135 mm).
constexpr double kChinAboveP99Mm = 20.0;

// The cut rim (head_cut_rim): the volume's outer 6 mm (about one occupancy cell of a head's model),
// from 20 mm above the eyes (above the brows: ears, face and neck stay out of it) up, and behind the
// eyes: in front of them the volume's face box ends 55 mm ahead of the eyes, and the two real
// captures' foreheads reach it (their depth is loosest there), while hats, buns and tall hair stand
// out above and behind (docs/room-training.md, "Hair, hats and a cut subject").
constexpr double kCutRimMm = 6.0, kCutRimAboveEyesMm = 20.0;

// The nape: the space under the back of the skull and behind the neck, which side views see only
// against the wall. The bare head (head_clear_core) and the neck's keep zone (head_clear_keep) end in
// front of it: behind kNapeShare of the head's length from the glabella (156 mm behind the eyes for
// the p99 head's 214 mm; the procedural heads' throats lie ~46 mm behind them), and for the skull
// only below kNapeBelowEyesMm under the eyes. In the keep zone a side view's wall would get the
// binary prior only, and in the core the gate stays shut until the room model has learnt the wall
// behind it, so the wall would stay there as a ghost. In the nape the clearing leans towards the
// room, as in the hair margins: a real nape or hair there stays where its colour differs from the
// room's (docs/room-training.md, "Zones").
constexpr double kNapeShare = 0.8, kNapeBelowEyesMm = 40.0;
double nape_z_mm(const fit::HeadExtents& e) { return e.glabella_ahead_mm - kNapeShare * e.head_length_mm; }

// An axis-aligned shape of the head frame spanning [lo, hi] (mm).
OrientedShape span(OrientedShape::Kind kind, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  OrientedShape s;
  s.kind = kind;
  for (int a = 0; a < 3; ++a)
    s.center[a] = float(0.5 * (lo[a] + hi[a])), s.half[a] = float(0.5 * (hi[a] - lo[a]));
  return s;
}

// The oriented head box in the head frame (mm), as fit::head_box_from_frame places it, and the same
// grown by loose hair: `side` mm sideways, `loose` mm upwards and backwards (the volumes' clips).
using Span = fit::HeadSpanMm;
using fit::declared_hair_mm;
using fit::head_box_span_mm;
Span loose_hair_span(const fit::HeadExtents& e, double side = kLooseHairMm, double loose = kLooseHairMm) {
  Span s = head_box_span_mm(e);
  s.lo.x() -= side, s.hi.x() += side;
  s.lo.z() -= loose, s.hi.y() += loose;
  return s;
}

// The skull with `hair` mm of hair above and behind it and the ears: from the back of the hair to in
// front of the glabella, from chin level to the top of the hair, as wide as the standard box (head
// breadth + the ears' and side hair's margin) and `side` mm beyond that, and `loose` mm of loose hair
// above, behind and below.
OrientedShape skull_mm(const fit::HeadExtents& e, double hair, double side, double loose) {
  const double half_x = 0.5 * e.head_breadth_mm + e.side_margin_mm + side;
  const double back = e.head_length_mm - e.glabella_ahead_mm + hair, top = e.vertex_above_eyes_mm + hair;
  return span(OrientedShape::Kind::Ellipsoid, {-half_x, -e.chin_below_eyes_mm - loose, -back - loose},
              {half_x, top + loose, e.glabella_ahead_mm + e.front_margin_mm});
}

// How much further the declared hair (beyond the standard) widens each side (fit::head_box_span_mm).
double side_hair_mm(const fit::HeadExtents& e) { return fit::kSideHairShare * declared_hair_mm(e); }

// The skull with `hair` mm of hair (skull_mm) in two parts: as wide as the standard skull below the
// eyes, and wider by the declared hair's side share from eye level up. Hats, buns and crowns flare
// above the brows; beside the jaw and the neck a frontal capture's room stays out.
void add_declared_skull(nerf::SubjectVolume& v, const fit::HeadExtents& e, double hair, double side,
                        double loose) {
  v.parts.push_back(skull_mm(e, hair, side, loose));
  OrientedShape wide = skull_mm(e, hair, side + side_hair_mm(e), loose);
  wide.y_from = -wide.center[1] / wide.half[1];  // eye level (head-frame y = 0) up
  v.parts.push_back(wide);
}

// `s` with its back (its lowest z) moved to `back`, its front kept.
OrientedShape with_back_at(OrientedShape s, double back) {
  const double front = double(s.center[2] + s.half[2]);
  s.center[2] = float(0.5 * (back + front)), s.half[2] = float(0.5 * (front - back));
  return s;
}

// The head's parts (skull, face, neck) for extents `e` with loose hair around the skull: `side` mm
// sideways, `loose` mm behind, above and below it. With `without_nape`, the neck ends at the nape
// (nape_z_mm), and so does the standard skull below kNapeBelowEyesMm under the eyes (the full skull
// above that height, a shorter copy of it below).
nerf::SubjectVolume head_parts_mm(const fit::HeadExtents& e, double side, double loose,
                                  bool without_nape = false) {
  const Span box = head_box_span_mm(e);
  const double bottom = -box.lo.y(), front = box.hi.z();
  nerf::SubjectVolume v;
  // The skull with at most the standard hair; more hair adds a longer ellipsoid, and a wider one above
  // the eyes (stretching the first would narrow it at the ears and the jaw).
  OrientedShape skull = skull_mm(e, e.hair_mm - declared_hair_mm(e), side, loose);
  if (without_nape) {
    v.parts.push_back(with_back_at(skull, nape_z_mm(e)));
    skull.y_from = float((-kNapeBelowEyesMm - skull.center[1]) / skull.half[1]);
  }
  v.parts.push_back(skull);
  if (declared_hair_mm(e) > 0.0) add_declared_skull(v, e, e.hair_mm, side, loose);
  // Face and jaw: the front half of the head, head-breadth wide, from below the chin (beard) to the
  // forehead, to the front of the box (nose tip and margin).
  v.parts.push_back(
      span(OrientedShape::Kind::Box,
           {-0.5 * e.head_breadth_mm, -(e.chin_below_eyes_mm + e.front_margin_mm), -0.5 * e.head_length_mm},
           {0.5 * e.head_breadth_mm, 0.5 * e.vertex_above_eyes_mm, front}));
  // Neck (and hair falling on it): an ellipsoid centred on the box's bottom under the skull's
  // middle, reaching up to eye level, head-breadth wide and a head length deep, so the box's bottom
  // keeps the neck and what hangs behind it.
  const double skull_mid = -0.5 * (e.head_length_mm - 2.0 * e.glabella_ahead_mm);
  const OrientedShape neck =
      span(OrientedShape::Kind::Ellipsoid,
           {-0.5 * e.head_breadth_mm, -2.0 * bottom, skull_mid - 0.5 * e.head_length_mm},
           {0.5 * e.head_breadth_mm, 0.0, skull_mid + 0.5 * e.head_length_mm});
  v.parts.push_back(without_nape ? with_back_at(neck, nape_z_mm(e)) : neck);
  return v;
}

}  // namespace

nerf::SubjectVolume head_volume_mm(const fit::HeadExtents& e, HeadVolumeShape shape) {
  if (shape == HeadVolumeShape::OrientedBox) {
    const Span box = head_box_span_mm(e);
    nerf::SubjectVolume v;
    v.parts.push_back(span(OrientedShape::Kind::Box, box.lo, box.hi));
    v.what = "the oriented head box";
    return v;
  }
  nerf::SubjectVolume v = head_parts_mm(e, kLooseHairMm, kLooseHairMm);
  const Span loose_box = loose_hair_span(e);
  v.clip = span(OrientedShape::Kind::Box, loose_box.lo, loose_box.hi);
  v.what = "the head's volume in the oriented head box (skull and hair, face, neck; capture/head_volume.h)";
  return v;
}

nerf::SubjectVolume head_clear_core_mm(const fit::HeadExtents& e) {
  fit::HeadExtents bare = e;
  bare.hair_mm = 0.0;
  // As wide as the head volume (the ears and what stands out beside them stay in the core).
  nerf::SubjectVolume v = head_parts_mm(bare, kLooseHairMm, 0.0, /*without_nape=*/true);
  // Hair declared beyond the standard (a bun, a hat) is the subject's, not a margin: it joins the
  // core, and only the standard margin beyond it leans towards the room.
  const double declared = declared_hair_mm(e), standard = e.hair_mm - declared;
  if (declared > 0.0) add_declared_skull(v, e, declared, kLooseHairMm, 0.0);
  // The volume's clip without the standard hair above and behind (the neck's ellipsoid ends at its
  // bottom).
  Span box = loose_hair_span(e, kLooseHairMm, 0.0);
  box.hi.y() -= standard, box.lo.z() += standard;
  v.clip = span(OrientedShape::Kind::Box, box.lo, box.hi);
  v.what =
      "the bare head (skull, face and neck without the hair behind and above, nor the nape; "
      "capture/head_volume.h)";
  return v;
}

nerf::SubjectVolume head_clear_keep_mm(const fit::HeadExtents& e) {
  // The head volume's clip from the average chin down (chin_below_eyes_mm is the p99 chin, ~20 mm
  // below the average one: keeping a long face's chin costs only its clearing there).
  Span keep = loose_hair_span(e);
  keep.hi.y() = -(e.chin_below_eyes_mm - kChinAboveP99Mm);
  keep.lo.z() = std::max(keep.lo.z(), nape_z_mm(e));  // not the nape
  // Only as wide as the head (p99 breadth), which no jaw or neck exceeds: beside the neck the volume
  // holds only loose hair and the ears' margin, and a side view sees that space against the wall,
  // not the body. With the binary prior there a wall of the skin's colour was painted beside the
  // neck as a solid slab (the synthetic pale selfie's leak; docs/room-training.md, "Zones").
  keep.lo.x() = -0.5 * e.head_breadth_mm, keep.hi.x() = 0.5 * e.head_breadth_mm;
  nerf::SubjectVolume v;
  v.parts.push_back(span(OrientedShape::Kind::Box, keep.lo, keep.hi));
  v.what = "the head box below the chin, in front of the nape (the neck; capture/head_volume.h)";
  return v;
}

nerf::SubjectVolume head_room_body_mm(const fit::HeadExtents& e) {
  const Span box = loose_hair_span(e);
  const double reach = 1000.0;  // beyond the room's cutout margin below, beside, in front and behind
  nerf::SubjectVolume v;
  v.parts.push_back(span(OrientedShape::Kind::Box,
                         {box.lo.x() - reach, box.lo.y() - reach, box.lo.z() - reach},
                         {box.hi.x() + reach, box.lo.y(), box.hi.z() + reach}));
  v.what = "below the head box (the neck's base and the shoulders: the room's; capture/head_volume.h)";
  return v;
}

nerf::SubjectRim head_cut_rim_mm(const fit::HeadExtents& e) {
  nerf::SubjectRim rim;
  rim.inner = head_volume_mm(e).grown(-float(kCutRimMm));
  const Span box = loose_hair_span(e);
  const double reach = 1000.0;  // beyond the volume above, behind and beside it
  rim.watch.parts.push_back(span(OrientedShape::Kind::Box,
                                 {box.lo.x() - reach, kCutRimAboveEyesMm, box.lo.z() - reach},
                                 {box.hi.x() + reach, box.hi.y() + reach, 0.0}));
  rim.watch.what = "the head volume's rim above the brows and behind the eyes (capture/head_volume.h)";
  // Its sides: beyond the head box's sides (breadth, side margin and the declared hair's share).
  const Span head = head_box_span_mm(e);
  for (double sign : {-1.0, 1.0}) {
    const double x0 = sign * head.hi.x(), x1 = sign * (head.hi.x() + reach);
    rim.sides.parts.push_back(span(OrientedShape::Kind::Box,
                                   {std::min(x0, x1), kCutRimAboveEyesMm, box.lo.z() - reach},
                                   {std::max(x0, x1), box.hi.y() + reach, 0.0}));
  }
  rim.sides.what = "the rim's sides (capture/head_volume.h)";
  return rim;
}

nerf::SubjectRim head_cut_rim(const fit::HeadBox& box) {
  const nerf::SubjectRim mm = head_cut_rim_mm(box.extents);
  return {to_scene(mm.inner, box), to_scene(mm.watch, box), to_scene(mm.sides, box)};
}

nerf::SubjectVolume to_scene(const nerf::SubjectVolume& mm, const fit::HeadBox& box) {
  const double s = 1.0 / box.head.mm_per_unit;
  auto map = [&](const OrientedShape& in) {
    OrientedShape out = in;
    Eigen::Vector3d c =
        box.anchor + box.axes * (s * Eigen::Vector3d(in.center[0], in.center[1], in.center[2]));
    for (int a = 0; a < 3; ++a) {
      out.center[a] = float(c[a]);
      out.half[a] = float(in.half[a] * s);
      // The shape's axes are the head frame's (mm shapes are axis-aligned there).
      Eigen::Vector3d local = Eigen::Vector3d::Zero();
      for (int b = 0; b < 3; ++b) local += double(in.axes[a][b]) * box.axes.col(b);
      for (int b = 0; b < 3; ++b) out.axes[a][b] = float(local[b]);
    }
    return out;
  };
  nerf::SubjectVolume v;
  for (const OrientedShape& p : mm.parts) v.parts.push_back(map(p));
  if (mm.clip) v.clip = map(*mm.clip);
  v.what = mm.what;
  return v;
}

nerf::SubjectVolume head_volume(const fit::HeadBox& box, HeadVolumeShape shape) {
  return to_scene(head_volume_mm(box.extents, shape), box);
}

nerf::SubjectVolume head_clear_keep(const fit::HeadBox& box) {
  return to_scene(head_clear_keep_mm(box.extents), box);
}

nerf::SubjectVolume head_room_body(const fit::HeadBox& box) {
  return to_scene(head_room_body_mm(box.extents), box);
}

nerf::SubjectVolume head_clear_core(const fit::HeadBox& box) {
  return to_scene(head_clear_core_mm(box.extents), box);
}

}  // namespace lorgnette::capture
