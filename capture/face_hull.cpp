// The face's and the neck's regions of a head box; see face_hull.h.
#include "capture/face_hull.h"

#include <cmath>

#include "capture/head_volume.h"
#include "fit/landmark_ids.h"
#include "fit/mean_face.h"
#include "fit/scale_chain.h"

namespace lorgnette::capture {
namespace {

// The jaw contour's points below the ears (0-1 and 15-16 lie at the tragus, beside the eyes, where a
// side view sees them against the hair or the room), then brows, nose, eyes and mouth.
constexpr int kContourFirst = 2, kContourLast = 14, kInnerFirst = 17, kCount = 68;

nerf::Vec3f to_vec3f(const Eigen::Vector3d& p) { return {float(p.x()), float(p.y()), float(p.z())}; }

// The jaw contour in the scene, from the mean face posed by the box's head frame. A contour landmark is
// where the face's outline meets what lies behind it in a photo, so every photo sees a different line
// on the skin, and rays that graze a convex face meet in front of it: triangulated, the contour of a
// +-50 deg arc lies 20-45 mm in front of the jaw, and a view turned 30 deg sees it beside the face, in
// the air. The mean face's contour (fit/mean_face.h) lies on an average jaw; it is placed as the head
// box's anchor is (the eye corners' centroid at the inner corners' depth) at the head frame's scale.
std::vector<Eigen::Vector3d> mean_face_contour(const fit::HeadBox& box) {
  const fit::Face68& mean = fit::builtin_mean_face();
  const Eigen::Vector3d anchor = fit::face_anchor(mean);
  std::vector<Eigen::Vector3d> contour;
  for (int k = kContourFirst; k <= kContourLast; ++k)
    contour.push_back(box.anchor + box.axes * ((mean[size_t(k)] - anchor) / box.head.mm_per_unit));
  return contour;
}

}  // namespace

std::vector<nerf::SolidHull> head_solid_hulls(const fit::HeadBox& box, const NeckCoreMm& neck) {
  std::vector<nerf::SolidHull> hulls;
  if (box.landmarks.size() != size_t(kCount) || box.landmark_ok.size() != size_t(kCount) ||
      !(box.head.mm_per_unit > 0.0))
    return hulls;
  nerf::SolidHull face;
  face.name = "face";
  face.facing = to_vec3f(box.head.d_fwd);
  for (int k = kInnerFirst; k < kCount; ++k)
    if (box.landmark_ok[size_t(k)]) face.points.push_back(to_vec3f(box.landmarks[size_t(k)]));
  if (face.points.size() >= 3) {
    for (const Eigen::Vector3d& p : mean_face_contour(box)) face.points.push_back(to_vec3f(p));
    hulls.push_back(face);
  }
  // The certain interior's parts (head_solid_core_mm's order: behind the face, the neck's core, the
  // skull), each a convex solid inside the head, seen from any side.
  const nerf::SubjectVolume core = head_solid_core(box, neck);
  const char* names[] = {"cheeks and jaw", "neck", "skull"};
  for (size_t i = 0; i < core.parts.size() && i < 3; ++i)
    hulls.push_back(nerf::convex_part_hull(core.parts[i], names[i]));
  return hulls;
}

nerf::SubjectVolume head_solid_core_mm(const NeckCoreMm& neck) {
  nerf::SubjectVolume v;
  nerf::OrientedShape face;
  face.kind = nerf::OrientedShape::Kind::Ellipsoid;
  face.center = {0.0f, -40.0f, -70.0f};
  face.half = {55.0f, 65.0f, 40.0f};
  v.parts.push_back(face);
  nerf::OrientedShape core;
  core.kind = nerf::OrientedShape::Kind::Cylinder;
  core.center = {0.0f, -float(0.5 * (neck.top_below_eyes + neck.bottom_below_eyes)),
                 -float(neck.behind_eyes)};
  core.half = {float(neck.radius), float(0.5 * (neck.bottom_below_eyes - neck.top_below_eyes)),
               float(neck.radius)};
  v.parts.push_back(core);
  nerf::OrientedShape skull;
  skull.kind = nerf::OrientedShape::Kind::Ellipsoid;
  skull.center = {0.0f, 30.0f, -75.0f};
  skull.half = {58.0f, 58.0f, 68.0f};
  v.parts.push_back(skull);
  v.what =
      "the head's certain interior (behind the face, in the skull, the neck's core; capture/face_hull.h)";
  return v;
}

nerf::SubjectVolume head_solid_core(const fit::HeadBox& box, const NeckCoreMm& neck) {
  return to_scene(head_solid_core_mm(neck), box);
}

nerf::SubjectVolume head_solid_reach_mm(const NeckCoreMm& neck) {
  nerf::SubjectVolume v = head_solid_core_mm(neck);
  const float s = float(1.0 + kSkullReachSigmas * fit::kMeanFaceRelativeUncertainty);
  nerf::OrientedShape& skull = v.parts[kSolidSkullPart];
  for (int a : {1, 2}) skull.center[a] *= s, skull.half[a] *= s;  // up and back; not its width
  v.what =
      "the head's certain interior with its skull stretched up and back for the scale's error "
      "(capture/face_hull.h)";
  return v;
}

nerf::SubjectVolume head_solid_reach(const fit::HeadBox& box, const NeckCoreMm& neck) {
  return to_scene(head_solid_reach_mm(neck), box);
}

nerf::SubjectAxis head_neck_base(const fit::HeadBox& box, const NeckCoreMm& neck) {
  const Eigen::Vector3d mm(0.0, fit::head_box_span_mm(box.extents).lo.y(), -neck.behind_eyes);
  const Eigen::Vector3d p = box.anchor + box.axes * (mm / box.head.mm_per_unit);
  const Eigen::Vector3d up = box.axes.col(1).normalized();
  nerf::SubjectAxis a;
  for (int i = 0; i < 3; ++i) a.point[i] = float(p[i]), a.up[i] = float(up[i]);
  return a;
}

}  // namespace lorgnette::capture
