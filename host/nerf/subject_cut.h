// Whether a subject volume cut the subject it was meant to hold: a hat, a bun or tall hair that stands
// out of a head's volume (capture/head_volume.h) is trained only up to the volume's boundary, so the
// views see a flat cut there. After training, views of the capture are marched through the model and
// the opacity they see is split by where it lies: the share in the volume's rim (SubjectRim, its
// outer 6 mm above the brows and behind the eyes) is near zero for a head inside the volume and
// larger where the volume cut the subject (docs/room-training.md, "Hair, hats and a cut subject").
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "common/camera_types.h"
#include "host/nerf/model.h"
#include "host/nerf/subject_volume.h"

namespace lorgnette::nerf {

// Densities at model-normalised positions ([0, 1)^3 of the model's box): sigma[i] for points[i].
using DensityAt = std::function<void(const std::vector<Vec3f>& points, std::vector<float>& sigma)>;

struct SeenOpacity {
  // Compositing weight (T * alpha) summed over the rays: in each zone (zone k at in_zone[k - 1]), and
  // in all.
  std::vector<double> in_zone;
  double total = 0.0;
  size_t rays = 0;
  double share(int zone) const { return total > 0.0 ? in_zone[size_t(zone - 1)] / total : 0.0; }
};

// The opacity the cameras see: every `stride`-th pixel's ray (scene frame, mapped into the model's
// box by `norm`) marched at `step` through the box's occupied cells of `occ`, the samples' densities
// from `density`, each sample's weight T * (1 - exp(-sigma * step)) added to `total` and to the zone
// `zone_of` gives the sample's scene-frame position (1..zones; 0: none).
SeenOpacity seen_opacity(const std::vector<Camera>& cameras, const Aabb& box, const SceneNormalisation& norm,
                         float step, const OccupancyGrid& occ, uint32_t stride, const DensityAt& density,
                         int zones, const std::function<int(const Vec3f&)>& zone_of);

// The rim's share of the seen opacity at or above which the subject counts as cut: a crown the volume
// cut reads 0.67-0.82 %, heads inside it 0.016 % at most (curls), so 0.1 % lies ~6x from both
// (docs/room-training.md, "Hair, hats and a cut subject").
constexpr double kSubjectCutShare = 0.001;

struct SubjectCutReport {
  bool checked = false;  // a rim was given and the views saw the subject
  // Shares of the seen opacity in the rim outside its sides (a head's top and back), and in its sides.
  double rim_share = 0.0, sides_share = 0.0;
  bool cut() const { return checked && (rim_share >= kSubjectCutShare || sides_share >= kSubjectCutShare); }
  std::string summary() const;
  // What to do when cut ("" otherwise): where the cut lies, and a larger --hair, which moves both.
  std::string advice() const;
};

// seen_opacity of `model` from up to 12 of `cameras` (evenly spread, ~64 rays across each), the rim
// outside its sides as zone 1 and its sides as zone 2.
SubjectCutReport check_subject_cut(NerfModel& model, const std::vector<Camera>& cameras,
                                   const SubjectRim& rim);

}  // namespace lorgnette::nerf
