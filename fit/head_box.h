// The subject box of a head capture from its posed photos: dlib's 68 landmarks are detected on an
// evenly spaced subset of the photos, triangulated robustly (fit/triangulate.h), the mean face is
// aligned to them (fit/head_frame.h: the head's axes and millimetres per scene unit), and a box
// sized from anthropometric head extents (millimetres, see HeadExtents) is placed in that head frame.
// The result is the scene-axis bounding box of the oriented head box, the "aabb" a NeRF of the head
// trains in (so the room behind the subject stays outside). Too few faces, or landmarks that do not
// triangulate, throw std::runtime_error saying how many photos were tried, how many showed a face,
// and what to do instead.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/camera_types.h"
#include "fit/head_frame.h"
#include "fit/landmarks_dlib.h"
#include "fit/triangulate.h"
#include "host/util/image_io.h"

namespace lorgnette::fit {

// Head extents in millimetres, measured from the face's anchor: x = the midpoint of the outer eye
// corners, y = eye level (mean height of the four eye corners), z = the inner eye corners' depth.
// Sources: ANSUR II (Gordon et al. 2014, US Army anthropometric survey; means men / women) for
// head breadth and length; Farkas, "Anthropometry of the Head and Face" (1994) for facial heights
// and nose projection; the 68-point mean face (fit/mean_face.h) for where the eye
// corners, the chin and the nose tip sit. Values are about the 99th percentile of adult men, so
// ordinary heads (and a +-10 % error of the mean-face scale) fit inside; the margins then add what
// the skull measurements leave out.
struct HeadExtents {
  // Euryon to euryon: ANSUR II 157 / 150 mm (SD ~5.5); p99 of men ~170.
  double head_breadth_mm = 170.0;
  // Beside the widest part of the skull: the ears stand ~15-25 mm off the side of the head at a
  // height where the head is ~10 mm narrower than at euryon, and side hair is of the same order.
  double side_margin_mm = 20.0;
  // Glabella to opisthocranion: ANSUR II 198 / 189 mm (SD ~7); p99 of men ~214.
  double head_length_mm = 214.0;
  // Soft-tissue glabella in front of the inner eye corners (the eyes sit in the orbits): ~12-18 mm.
  double glabella_ahead_mm = 15.0;
  // Eye level to vertex: total head height vertex-menton ~232 / 218 mm (Farkas) minus eye level to
  // menton (114 mm in the mean face) gives ~118 mm for men; p99 ~135.
  double vertex_above_eyes_mm = 135.0;
  // Eye level to menton: 114 mm in the mean face, endocanthion-gnathion ~120 mm in men (Farkas,
  // SD ~6); p99 ~135.
  double chin_below_eyes_mm = 135.0;
  // Pronasale in front of the inner eye corners: 36.5 mm in the mean face; p99 ~45 (long noses).
  double nose_ahead_mm = 45.0;
  double front_margin_mm = 10.0;  // lips, beard, a loose strand in front of the nose tip
  double hair_mm = 30.0;          // hair volume on top and at the back of the head
  double neck_mm = 40.0;          // neck kept below the chin (the rest is cut off by the box)
};

// Hair beyond the standard allowance (HeadExtents{}.hair_mm; train --hair: a bun, a hat, a crown):
// 0 for the standard extents.
double declared_hair_mm(const HeadExtents& e);

// Declared hair widens the box's sides by this share of itself on each side: hats, buns and crowns
// stand out less sideways than upwards (the Nefertiti bust's crown: docs/room-training.md, "Hair,
// hats and a cut subject"). The standard side margin already holds ordinary side hair and ears.
inline constexpr double kSideHairShare = 0.5;

// The oriented head box in head-frame millimetres from the anchor (x left, y up, z forward):
// head_box_from_frame's box before it is placed in the scene.
struct HeadSpanMm {
  Eigen::Vector3d lo, hi;
};
HeadSpanMm head_box_span_mm(const HeadExtents& e);

struct HeadBoxOptions {
  int max_photos = 24;        // photos tried, evenly spaced over the list (dlib costs ~0.1-0.3 s each)
  int min_faces = 3;          // photos with a face needed to triangulate
  int detect_max_side = 640;  // photos are shrunk to this for detection (faces in head captures are large)
  DetectorOptions detector;
  TriangulateOptions triangulate;
  std::string mean_face_path;  // empty: the built-in mean face (fit/mean_face.h)
  HeadExtents extents;
};

// One posed photo: the camera (intrinsics for the image's size, distortion included) and the image,
// in memory (`image`) or read from `path` when `image` is null.
struct PosedPhoto {
  Camera camera{};
  const Image* image = nullptr;
  std::string path;
};

struct HeadBox {
  Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();  // scene axes
  Eigen::Vector3d center = Eigen::Vector3d::Zero();       // the oriented box's centre (scene)
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();     // columns: head left, up, forward (scene)
  Eigen::Vector3d half_extent = Eigen::Vector3d::Zero();  // oriented half sizes along axes (scene units)
  Eigen::Vector3d anchor = Eigen::Vector3d::Zero();       // HeadExtents' origin (scene): eye level, mid eyes
  HeadExtents extents;                                    // the extents the box was sized from
  HeadFrame head;                                         // d_fwd, d_up, d_eye, mm per unit, PD
  int photos_tried = 0, faces_found = 0, landmarks_triangulated = 0;
  // The 68 triangulated landmarks (scene) and which of them triangulated (empty for a box built
  // from a frame alone): the face's region, which training checks for holes (capture/face_hull.h).
  std::vector<Eigen::Vector3d> landmarks;
  std::vector<bool> landmark_ok;
  std::string summary() const;  // one line for logs and reports
};

// The head box of a set of posed photos (throws as described at the top of the file).
HeadBox estimate_head_box(const std::vector<PosedPhoto>& photos, const HeadBoxOptions& options = {});

// The oriented box of a head frame anchored at `anchor` (scene; see HeadExtents for the anchor),
// without detection: the geometric half of estimate_head_box, exposed for tests.
HeadBox head_box_from_frame(const HeadFrame& head, const Eigen::Vector3d& anchor, const HeadExtents& extents);

// Indices of at most `count` entries spread evenly over [0, n) (first and last included).
std::vector<size_t> even_subset(size_t n, size_t count);

}  // namespace lorgnette::fit
