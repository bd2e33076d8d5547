// The regions of a head that its trained model must fill solidly, for training's check of its own
// output (host/nerf/subject_holes.h): the face, as the hull of its triangulated landmarks from the
// landmark head box (fit/head_box.h), and the head's certain interior (behind the face, the skull,
// the neck's core below the chin). Holes there are what the
// room model's separation takes from a face before a wall of the same colour (#41).
#pragma once
#include <cstddef>
#include <vector>

#include "fit/head_box.h"
#include "host/nerf/subject_volume.h"

namespace lorgnette::capture {

// The neck's core in the head frame (millimetres from HeadExtents' anchor: eye level, between the
// eyes, at the inner eye corners' depth; x left, y up, z forward): a vertical cylinder of this
// radius about an axis this far behind the anchor, between these depths below the eyes. The neck's
// axis lies ~90 mm behind the inner eye corners (the procedural heads: 92 mm; a neck of radius
// ~50 mm, circumference 32 cm, whose front, the throat, lies ~45 mm behind the eyes), and an average
// chin 114 mm below the eyes (the mean face). The core reaches down to the head box's bottom (p99 chin
// 135 mm + 40 mm of neck): rays down through the neck's lowest band end in the room's neck base below
// the box, which explains that band as well as the subject does, so it is the band that most needs the
// core's pull. A nod turns the head about the upper neck's joints, on the neck's axis ~45 mm below
// the eyes, so in the head's frame the neck's axis swings by (h - 45 mm) sin(nod) at h below the eyes:
// at the box's bottom 23 mm for 10 deg and 34 mm for 15 deg, so the core (20 mm) stays inside a
// 50-60 mm neck for a nod of up to 13-18 deg against the body, less than a head bowed to look down at
// a phone (the lower neck bends with a real nod, so less moves than this bound; docs/room-training.md,
// "Known limits").
struct NeckCoreMm {
  double radius = 20.0, behind_eyes = 90.0, top_below_eyes = 125.0, bottom_below_eyes = 175.0;
};

// The regions training checks for holes: the face hull (the inner points 17-67 that triangulated,
// and the jaw contour from below the ears round the chin, 2-14, of the mean face posed by the head
// frame, since a triangulated contour lies in front of the jaw; facing the head's forward axis,
// judged from views within 50 deg of it) and the parts of the head's certain interior
// (head_solid_core: "cheeks and jaw" behind the face, the "neck" core, the "skull"), each a convex
// solid seen from any side, so a hole at the side or the top of the head is judged too; empty when the
// box holds no landmarks.
std::vector<nerf::SolidHull> head_solid_hulls(const fit::HeadBox& box, const NeckCoreMm& neck = {});

// The head's certain interior (nerf::SubjectZones::solid), in the head frame (mm, as NeckCoreMm) and
// in the scene: an ellipsoid behind the face, centred 70 mm behind the inner eye corners and 40 mm
// below the eyes, 55 mm to each side, 65 mm up and down and 40 mm deep, so its front lies 30 mm
// behind the eye corners' plane at the nose's height and ~43 mm at the cheeks 40 mm out (the mean
// face's cheeks lie 10-20 mm behind that plane, its eyeballs reach 25 mm; a face is 120-140 mm wide
// at the cheekbones); the skull's interior, an ellipsoid centred 75 mm behind the inner eye corners
// and 30 mm above the eyes, 58 mm to each side, 58 mm up and down and 68 mm deep (a small adult head,
// p1 of women: ~135 mm broad, ~173 mm from glabella, 15 mm ahead of the eye corners, to the back,
// ~100 mm from the eyes to the vertex, so it stays ~10 mm inside the sides, ~15 mm inside the back,
// ~20 mm inside the forehead and ~12 mm below the top); and the neck's core (NeckCoreMm, a cylinder). Rays
// that miss it get no pull (the rim of the head, where the evidence is ambiguous), so it reaches as close to
// the skin as a small head allows: on six procedural heads every point of it lies 4 mm or more inside the
// skin, the face's and the skull's parts 6.5 mm (tests/capture/face_hull_test.cpp), so a ray from any
// training view through it passes through the subject.
nerf::SubjectVolume head_solid_core_mm(const NeckCoreMm& neck = {});
// The skull's index among head_solid_core's parts (behind the face, the neck's core, the skull).
inline constexpr size_t kSolidSkullPart = 2;
nerf::SubjectVolume head_solid_core(const fit::HeadBox& box, const NeckCoreMm& neck = {});

// Where a ray counts as crossing the certain interior, before training grows it by --solid-reach
// (nerf::SubjectZones::reach): head_solid_core with the skull's part stretched up and back from the
// anchor by 1 + kSkullReachSigmas x the mean face's scale uncertainty (fit::kMeanFaceRelativeUncertainty,
// 10 % at one sigma). The skull's top and back are the head's only points that no landmark bounds (its
// top lies 80 mm above the brows, its back 100 mm behind the jaw contour's ends): their millimetres
// are the mean face's, and a scale read high (the procedural heads' captures read -4 to +21 %) moves
// them inwards, the top by about 9 mm per 10 %, leaving the crown's top band, where a selfie's views
// see the head against the wall, to the colour alone: hair or skin of the wall's colour there became
// holes. Two sigma, because a hole is the broken product and haze at the head's edge the lesser flaw
// (#41): stretched, a scale read 20 % high still reaches as high as the interior itself with a true
// scale; with a true scale its top rises 18 mm and its back 29 mm, and beside a small bald head (a p1
// skull) it stands up to 15 mm further outside the skin than the interior's own reach: rays that
// graze that band keep no room-explained clearing, so haze there stays (it fills nothing: the pull
// stays in head_solid_core). Its width stays: the jaw contour's landmarks span it. The face's and
// the neck's parts keep their sizes.
inline constexpr double kSkullReachSigmas = 2.0;
nerf::SubjectVolume head_solid_reach_mm(const NeckCoreMm& neck = {});
nerf::SubjectVolume head_solid_reach(const fit::HeadBox& box, const NeckCoreMm& neck = {});

// Where the neck leaves the head box (nerf::SubjectZones::base): the neck's axis (NeckCoreMm's, the
// head's up direction) at the box's bottom.
nerf::SubjectAxis head_neck_base(const fit::HeadBox& box, const NeckCoreMm& neck = {});

}  // namespace lorgnette::capture
