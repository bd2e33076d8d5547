// The face's and the neck's regions of a head box; see face_hull.h.
#include "capture/face_hull.h"

#include <cmath>

#include "capture/head_volume.h"

namespace lorgnette::capture {
namespace {

// The jaw contour's points below the ears (0-1 and 15-16 lie at the tragus, beside the eyes, where a
// side view sees them against the hair or the room), then brows, nose, eyes and mouth.
constexpr int kContourFirst = 2, kContourLast = 14, kInnerFirst = 17, kCount = 68;

nerf::Vec3f to_vec3f(const Eigen::Vector3d& p) { return {float(p.x()), float(p.y()), float(p.z())}; }

}  // namespace

std::vector<nerf::SolidHull> head_solid_hulls(const fit::HeadBox& box, const NeckCoreMm& neck) {
  std::vector<nerf::SolidHull> hulls;
  if (box.landmarks.size() != size_t(kCount) || box.landmark_ok.size() != size_t(kCount) ||
      !(box.head.mm_per_unit > 0.0))
    return hulls;
  nerf::SolidHull face;
  face.name = "face";
  face.facing = to_vec3f(box.head.d_fwd);
  for (int k = kContourFirst; k < kCount; ++k)
    if ((k <= kContourLast || k >= kInnerFirst) && box.landmark_ok[size_t(k)])
      face.points.push_back(to_vec3f(box.landmarks[size_t(k)]));
  if (face.points.size() >= 3) hulls.push_back(face);
  nerf::SolidHull core;
  core.name = "neck";
  core.facing = face.facing;
  core.max_view_deg = 180.0f;
  const double unit = 1.0 / box.head.mm_per_unit;
  const Eigen::Vector3d axis = box.anchor - box.head.d_fwd * (neck.behind_eyes * unit);
  for (double below : {neck.top_below_eyes, neck.bottom_below_eyes})
    for (int i = 0; i < 12; ++i) {
      const double a = 2.0 * M_PI * i / 12.0;
      const Eigen::Vector3d p =
          axis - box.head.d_up * (below * unit) +
          (box.head.d_eye * std::cos(a) + box.head.d_fwd * std::sin(a)) * (neck.radius * unit);
      core.points.push_back(to_vec3f(p));
    }
  hulls.push_back(core);
  return hulls;
}

nerf::SubjectVolume head_solid_core_mm(const NeckCoreMm& neck) {
  nerf::SubjectVolume v;
  nerf::OrientedShape face;
  face.kind = nerf::OrientedShape::Kind::Ellipsoid;
  face.center = {0.0f, -40.0f, -70.0f};
  face.half = {45.0f, 60.0f, 40.0f};
  v.parts.push_back(face);
  nerf::OrientedShape core;
  core.kind = nerf::OrientedShape::Kind::Ellipsoid;
  core.center = {0.0f, -float(0.5 * (neck.top_below_eyes + neck.bottom_below_eyes)),
                 -float(neck.behind_eyes)};
  core.half = {float(neck.radius), float(0.5 * (neck.bottom_below_eyes - neck.top_below_eyes)) + 10.0f,
               float(neck.radius)};
  v.parts.push_back(core);
  nerf::OrientedShape skull;
  skull.kind = nerf::OrientedShape::Kind::Ellipsoid;
  skull.center = {0.0f, 30.0f, -75.0f};
  skull.half = {50.0f, 50.0f, 60.0f};
  v.parts.push_back(skull);
  v.what =
      "the head's certain interior (behind the face, in the skull, the neck's core; capture/face_hull.h)";
  return v;
}

nerf::SubjectVolume head_solid_core(const fit::HeadBox& box, const NeckCoreMm& neck) {
  return to_scene(head_solid_core_mm(neck), box);
}

}  // namespace lorgnette::capture
