// Holes in the trained subject: the product's check of its own output. A room model that takes part
// of a face for the wall behind it (a pale face before a pale wall) leaves the face transparent there,
// and every try-on then shows a head with holes. After training, the regions the subject must fill
// solidly (SolidHull: the hull of a face's landmarks; the parts of the head's certain interior, the
// skull's, behind the face and the neck's core, seen from any side) are projected into the training
// views, rays through pixels inside each projected hull (a landmark hull shrunk towards its centre, so
// its own rim, where the landmarks lie on the face's edge, is not judged) are marched through the
// model, and the share of those rays whose opacity stays under 0.5, per region, is the figure: near 0
// for a whole head, the area of the holes for a broken one. The NeRF core knows nothing about faces: the
// hulls come from the capture (capture/face_hull.h).
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

// A region seen by fewer rays than this in a view (a sliver of its outline) does not set that view's
// worst figure: one grazing ray would be its whole share.
constexpr size_t kMinViewRays = 50;

struct HoleCheckOptions {
  size_t max_views = 12;      // evenly spread over the cameras
  uint32_t rays_across = 96;  // ray grid: the view's longer side / this (pixels between rays)
  float shrink = kHullShrink;
};

// One region's rays (a hull, or hulls of one name) and its hole rays.
struct RegionHoles {
  std::string name;
  size_t rays = 0, holes = 0;
  double share() const { return rays ? double(holes) / double(rays) : 0.0; }
};

// Each region is judged on its own share, so a hole in the face is not diluted by the many whole rays
// through the skull behind it: the figure is the worst region's.
struct HoleReport {
  bool checked = false;     // some hull was seen from some view
  double holes = 0.0;       // the worst region's share of rays with opacity < kHoleOpacity
  double worst_view = 0.0;  // the same in the worst view (regions with kMinViewRays rays or more there)
  size_t rays = 0, views = 0;
  std::vector<RegionHoles> regions;  // in the hulls' order, one per name
  std::vector<std::string> where;    // per region with holes: "face 3.2 %"
  bool broken() const { return checked && holes >= kSubjectHoleShare; }
  // The name of the region with the largest share ("face and head" when no region was recorded).
  std::string worst_region() const;
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
