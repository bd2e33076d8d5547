// The volume a head may occupy in its landmark head box (fit/head_box.h), as the subject volume of a
// mask-less capture's model (host/nerf/subject_volume.h): the oriented head box (not its axis-aligned
// bounds, whose corners hold the room), and within it a head shape sized from the same
// anthropometric extents (fit::HeadExtents): the skull with its hair as an ellipsoid, the face and
// jaw in front of it, and the neck below it down to the box's bottom. Every part is sized from the
// p99 extents plus their margins, so ears, hair and neck stay in; what it removes is the box's
// corners behind and below the skull, where a wall close behind the subject otherwise gets
// rebuilt as part of the subject (docs/room-training.md, "The head's volume"). Hair beyond the
// standard HeadExtents::hair_mm (train --hair: a bun, a hat) adds a longer and wider skull ellipsoid
// and joins the clearing's core (docs/room-training.md, "Hair, hats and a cut subject").
#pragma once
#include "fit/head_box.h"
#include "host/nerf/subject_volume.h"

namespace lorgnette::capture {

enum class HeadVolumeShape { OrientedBox, Head };

// The volume in the head frame: millimetres from HeadExtents' anchor (eye level, between the eyes),
// x = the head's left, y = up, z = forward.
nerf::SubjectVolume head_volume_mm(const fit::HeadExtents& extents,
                                   HeadVolumeShape shape = HeadVolumeShape::Head);

// The same volume placed in the scene (units of the head box's scene): its anchor, axes and scale.
nerf::SubjectVolume head_volume(const fit::HeadBox& box, HeadVolumeShape shape = HeadVolumeShape::Head);

// The part of the head box below the chin (from the average chin down to the box's bottom, as wide
// as the head's p99 breadth, in front of the nape), in the head frame (mm) and in the scene: the
// neck, which the body in the room model lies right behind, so the room's colour can match it
// without the neck being a backdrop. The room-explained clearing (nerf::SubjectZones::keep) leaves
// it out.
nerf::SubjectVolume head_clear_keep_mm(const fit::HeadExtents& extents);
nerf::SubjectVolume head_clear_keep(const fit::HeadBox& box);

// The bare head: the head volume's skull, face and neck at their p99 extents without the hair
// behind and above the skull (hair_mm and the loose hair there), as wide as the head volume (ears),
// without the nape (under the back of the skull, behind the neck: head_volume.cpp), in the head frame
// (mm) and in the scene. Outside it the clearing leans towards the room
// (nerf::SubjectZones::core).
nerf::SubjectVolume head_clear_core_mm(const fit::HeadExtents& extents);
nerf::SubjectVolume head_clear_core(const fit::HeadBox& box);

// Right below the head box (its bottom, across its width and depth with loose hair, and far beyond):
// the neck's base and the shoulders, which the room model holds (nerf::SubjectZones::body). The room's
// cutout grows the head volume by a margin on every side; below the box's bottom that margin was a
// band of neck and collar that neither model could hold, and the subject painted it onto its box's
// bottom edge, in front of and behind the neck (docs/room-training.md, "The head's volume"). In the
// head frame (mm) and in the scene.
nerf::SubjectVolume head_room_body_mm(const fit::HeadExtents& extents);
nerf::SubjectVolume head_room_body(const fit::HeadBox& box);

// Where a subject cut by the head volume shows the cut (nerf::SubjectRim, host/nerf/subject_cut.h): the
// head volume's outer 6 mm from 20 mm above the eyes up, behind the eyes. A hat, a bun or hair that stands
// out further than `--hair` allows is cut flat there; a head inside the volume leaves it empty (the hair
// allowance and the loose hair lie between the skull and the rim). Its sides (beyond the head box's
// sides, which `--hair` widens by fit::kSideHairShare of the declared hair) are reported apart. In the
// head frame (mm) and in the scene.
nerf::SubjectRim head_cut_rim_mm(const fit::HeadExtents& extents);
nerf::SubjectRim head_cut_rim(const fit::HeadBox& box);

// A head-frame (mm) volume mapped to the scene by the frame of `box`.
nerf::SubjectVolume to_scene(const nerf::SubjectVolume& mm, const fit::HeadBox& box);

}  // namespace lorgnette::capture
