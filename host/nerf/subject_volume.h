// The space a subject may occupy inside its model's box, when more is known than the box: a union
// of oriented ellipsoids and boxes (scene units), optionally clipped to one oriented box, and the
// permanent occupancy mask it gives the subject's model (cells outside never hold density, in
// training, in the subject region and in every render). A model's box is axis-aligned; a subject
// placed at an angle in it (a head tilted in the scene's axes) leaves corners that are not subject
// but that a mask-less capture fills with whatever is behind it (the wall). The NeRF core knows
// nothing about faces: capture/head_volume.h builds the volume of a head from its landmark box.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "host/nerf/snapshot.h"

namespace lorgnette::nerf {

using Vec3f = std::array<float, 3>;

struct OrientedShape {
  // Cylinder: an elliptic cylinder along the shape's second axis (|y| <= half[1], and x, z within the
  // ellipse of half sizes half[0], half[2]).
  enum class Kind : uint8_t { Box, Ellipsoid, Cylinder };
  Kind kind = Kind::Box;
  Vec3f center{0.0f, 0.0f, 0.0f};
  // The shape's own axes in scene coordinates (unit, orthogonal), and its half sizes along them.
  std::array<Vec3f, 3> axes{{{1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 1.0f}}};
  Vec3f half{0.0f, 0.0f, 0.0f};
  // The part holds only points whose local y is at least y_from * half[1] (-1: the whole shape), so
  // a part can end at a plane across its second axis (a head's wider hair from eye level up).
  float y_from = -1.0f;

  Vec3f local(const Vec3f& p) const;  // p in the shape's axes, relative to its centre
  bool contains(const Vec3f& p) const;
  // The same shape with every half size grown by `d` (scene units).
  OrientedShape grown(float d) const;
};

struct SubjectVolume {
  std::vector<OrientedShape> parts;   // union
  std::optional<OrientedShape> clip;  // the union is intersected with this (e.g. the oriented head box)
  std::string what;                   // one line for logs: what the volume is

  bool contains(const Vec3f& p) const;
  bool empty() const { return parts.empty(); }
  // Every part and the clip grown by `d` (scene units).
  SubjectVolume grown(float d) const;
};

// Where a subject that stands out of its volume is cut flat: points outside `inner` (the volume shrunk
// by a few mm; beyond the volume the mask leaves no density) and inside `watch` (for a head: above the
// brows and behind the eyes, where hats, buns and tall hair stand out). A subject inside the volume
// leaves it empty; one cut by the volume shows the cut there (host/nerf/subject_cut.h). `sides` is the
// part of it reported apart (a head's sides, which `train --hair` widens by half as much as it raises
// the top and back).
struct SubjectRim {
  SubjectVolume inner, watch, sides;
  bool empty() const { return watch.empty(); }
  // 0: not in the rim; 1: in the rim, outside `sides`; 2: in `sides`.
  int zone(const Vec3f& p) const {
    if (!watch.contains(p) || inner.contains(p)) return 0;
    return sides.contains(p) ? 2 : 1;
  }
};

// Points of the subject whose projection into a view outlines a region that the subject must fill
// solidly there (a face: the hull of its landmarks; host/nerf/subject_holes.h measures the holes in
// it), with the direction it faces: views more than `max_view_deg` from it see the region's points
// round its side, where their hull outlines air.
// A hull marked `convex_solid` is the surface of a convex solid that lies inside the subject (a part
// of its certain interior, SubjectZones::solid): every ray through its projection crosses the solid,
// so the whole projection is judged, from any side, without the shrink a landmark hull needs.
struct SolidHull {
  std::vector<Vec3f> points;  // scene frame
  Vec3f facing{0.0f, 0.0f, 1.0f};
  float max_view_deg = 50.0f;
  std::string name;  // for logs: "face", "skull", "neck"
  bool convex_solid = false;
};

// Points on the surface of an ellipsoid or cylinder part (an ellipsoid: a latitude-longitude net of
// `rings` x `segments` and the two poles; a cylinder: its two end ellipses of `segments` points each),
// as a convex_solid hull named `name`: the convex hull of their projection lies inside the part's
// projected outline.
SolidHull convex_part_hull(const OrientedShape& part, const std::string& name, int rings = 7,
                           int segments = 16);

// The subject's skin colours, as the loss compares a pixel with them (kernels/train/render.h
// render_ray_skin_like), sampled on the face at its landmarks in the training photos
// (capture/skin_colours.h): chromaticities (linear r and g over r + g + b), at most SKIN_REFS_MAX;
// `spread`, the largest distance of a sample from its nearest chromaticity here;
// and the luminance (linear) under which a pixel's chromaticity is too noisy to judge.
struct SkinChroma {
  std::vector<std::array<float, 2>> chroma;
  float spread = 0.0f;
  float lum_floor = 0.0f;
  // Colours (linear RGB) the photos show beside the neck where it leaves the head box, where a level
  // head has only the wall behind it: whether that wall may be skin (BackgroundOptions::keep_far_neck_mm).
  std::vector<std::array<float, 3>> beside_neck;
  // The chromaticities as render_ray_skin_like takes them: r, g pairs, one after the other.
  std::vector<float> pairs() const {
    std::vector<float> out;
    for (const auto& c : chroma) out.push_back(c[0]), out.push_back(c[1]);
    return out;
  }
};

// A point on an axis and the axis' direction (scene; `up` unit).
struct SubjectAxis {
  Vec3f point{0.0f, 0.0f, 0.0f}, up{0.0f, 1.0f, 0.0f};
};

// A subject's volume with the zones of the room model's clearing inside it (background_field.h;
// capture/head_volume.h builds them from a landmark head box). Empty zones do not apply.
struct SubjectZones {
  // Where the subject may be: its permanent occupancy mask and the room model's cutout.
  SubjectVolume volume;
  // Where the clearing does not apply (BackgroundOptions::room_clear): the part the room model's own
  // surfaces lie right behind (a head's neck, with the body below the box in the room model).
  SubjectVolume keep;
  // The bare subject (a head without the hair margins behind and above the skull): in `volume`
  // outside it, the clearing leans towards the room (BackgroundOptions::lean_gate).
  SubjectVolume core;
  // Not a clearing zone: where training checks, once done, whether the volume cut the subject.
  SubjectRim rim;
  // Where the room model holds what lies right below the volume (a head's neck base and shoulders,
  // below its box): the room's cutout around the volume (BackgroundOptions::volume_cutout_margin)
  // leaves it to the room, so no band below the volume belongs to neither model.
  SubjectVolume body;
  // Not a clearing zone: the regions the trained subject must fill solidly, seen from the training
  // views (subject_holes.h: holes in the face or the neck).
  std::vector<SolidHull> whole;
  // The subject's certain interior (a face behind its skin, the skull, a neck's core): every ray
  // through it ends in the subject, so the room-explained clearing never applies to such a ray and
  // the prior pulls it to opaque there (BackgroundOptions::solid_pull); its cells stay occupied.
  SubjectVolume solid;
  // Millimetres per scene unit of these volumes (0: unknown), for growths given in millimetres.
  float mm_per_unit = 0.0f;
  // The skin's colours (none: unknown), for the clearing in `keep` (BackgroundOptions::neck_clear).
  SkinChroma skin;
  // Where a ray counts as crossing `solid` before BackgroundOptions::solid_reach_mm's growth: `solid`
  // with each part that no landmark bounds (a head's skull) stretched for the scale's error
  // (capture/face_hull.h head_solid_reach); empty: `solid` itself.
  SubjectVolume reach;
  // Where the subject continues below its volume into the room's `body` (a head's neck leaving the
  // box's bottom; none: unknown): the far-wall rule counts the room's samples below there as the
  // subject's surroundings only within a column about this axis (BackgroundOptions::keep_far_neck_mm).
  std::optional<SubjectAxis> base;
};

// The occupancy mask of `volume` over `box` at res^3 cells (occ_word_count(res) words, the grid's
// cell order): a cell is allowed when its centre or one of its 8 corners lies in the volume, so no
// cell the volume reaches into is lost at the grid's resolution.
std::vector<uint32_t> volume_occupancy_mask(const SubjectVolume& volume, const Aabb& box, uint32_t res);

// The room model's occupancy mask over `room` at res^3 cells around a subject's volume: every cell
// allowed except those whose centre lies in `volume` grown by `margin` (scene units), unless it lies
// in `body` (SubjectZones::body: what lies right below the volume is the room's; empty: none).
std::vector<uint32_t> room_cutout_mask(const Aabb& room, const SubjectVolume& volume, float margin,
                                       const SubjectVolume& body, uint32_t res);

// Cells allowed by a mask (for logs and tests).
uint64_t mask_count(const std::vector<uint32_t>& mask);

}  // namespace lorgnette::nerf
