// Holes in the trained subject: the product's check of its own output. A room model that takes part
// of a face for the wall behind it (a pale face before a pale wall) leaves the face transparent there,
// and every try-on then shows a head with holes. After training, the regions the subject must fill
// solidly (SolidHull: the hull of a face's landmarks, a neck's core) are projected into the training
// views, rays through pixels inside each projected hull (shrunk towards its centre, so the hull's
// own rim, where the landmarks lie on the face's edge, is not judged) are marched through the model,
// and the share of those rays whose opacity stays under 0.5 is the figure: near 0 for a whole head,
// the area of the holes for a broken one. The NeRF core knows nothing about faces: the hulls come
// from the capture (capture/face_hull.h).
#pragma once
#include <string>
#include <vector>

#include "common/camera_types.h"
#include "host/nerf/model.h"
#include "host/nerf/subject_cut.h"
#include "host/nerf/subject_volume.h"

namespace lorgnette::nerf {

// A ray counts as a hole when its opacity is under this: the "transparent" (#41), the level
// at which a render over any background shows the background more than the subject.
constexpr double kHoleOpacity = 0.5;

// The share of a hull's rays that may be holes before the subject counts as broken: 1 % of a face's
// landmark hull (about 120 x 130 mm) is ~160 mm^2, a 14 mm disc, as large as a nostril's shadow and
// plainly visible in a try-on. A whole head's share is 0 up to the odd grazing ray (the synthetic
// heads, tests/host/nerf/subject_holes_test.cpp); the broken selfie lost ~10 % of its
// head's interior.
constexpr double kSubjectHoleShare = 0.01;

// Each hull's projection is shrunk towards its centre by this factor before rays are cast: the
// landmarks of a face's contour lie on its edge, and between them the hull's outline crosses air in
// front of a recessed mouth or beside a cheek seen at an angle (15 % of a face's half-width is ~9 mm).
constexpr float kHullShrink = 0.85f;

struct HoleCheckOptions {
  size_t max_views = 12;      // evenly spread over the cameras
  uint32_t rays_across = 96;  // ray grid: the view's longer side / this (pixels between rays)
  float shrink = kHullShrink;
};

struct HoleReport {
  bool checked = false;     // some hull was seen from some view
  double holes = 0.0;       // share of all hull rays with opacity < kHoleOpacity
  double worst_view = 0.0;  // the same in the worst view
  size_t rays = 0, views = 0;
  std::vector<std::string> where;  // per hull with holes: "face 3.2 %"
  bool broken() const { return checked && holes >= kSubjectHoleShare; }
  std::string summary() const;
  // What the shopper should film differently ("" when not broken).
  std::string advice() const;
};

// The opacity of rays through `hulls` seen from `cameras` (scene frame, mapped into the model's box by
// `norm`), marched at `step` through the occupied cells of `occ` with densities from `density` (at
// model-normalised points, as seen_opacity takes them).
HoleReport measure_holes(const std::vector<Camera>& cameras, const Aabb& box, const SceneNormalisation& norm,
                         float step, const OccupancyGrid& occ, const DensityAt& density,
                         const std::vector<SolidHull>& hulls, const HoleCheckOptions& options = {});

// measure_holes on a trained model, its field's densities.
HoleReport check_subject_holes(NerfModel& model, const std::vector<Camera>& cameras,
                               const std::vector<SolidHull>& hulls, const HoleCheckOptions& options = {});

}  // namespace lorgnette::nerf
