// The subject's skin colours from its training photos, for the room-explained clearing in the neck's
// keep zone (host/nerf/background_field.h, BackgroundOptions::neck_clear): the face is sampled at
// points placed by its triangulated landmarks (both cheeks below the eyes and the chin below the lower
// lip: bare skin on nearly every face, away from the eyes, brows, lips, nostrils and the highlights a
// forehead and a nose take), in every photo that sees the face within 35 deg of its front.
#pragma once
#include <array>
#include <vector>

#include "fit/head_box.h"
#include "host/nerf/subject_volume.h"

namespace lorgnette::capture {

struct SkinSampleOptions {
  double max_view_angle_deg = 35.0;  // a photo's angle from the face's front beyond which it is not sampled
  double patch_radius_mm = 4.0;      // each sample is the median of a patch this wide about its point
  // A pixel darker than this share of the darkest skin sample is not judged by its chromaticity: the
  // shadow under the jaw gets the fill light only, commonly a quarter of the key (2 stops), and
  // darker still the chromaticity is noise.
  double dark_share = 0.25;
  // A sample further than this (or 4 x the samples' median distance, if more) from their median
  // chromaticity missed the skin; a face's own skin varies by about 0.03 (blush against the chin).
  double outlier_cut = 0.04;
  int min_samples = 3;  // fewer: no skin colours (the keep zone keeps its binary prior)
  // Where the wall beside the neck is sampled (nerf::SkinChroma::beside_neck; head frame, mm): this far
  // to each side of the neck's axis (NeckCoreMm's), beyond a p99 man's neck (~70 mm) and the jaw's
  // angle (~60 mm), short of the shoulders' tops (~180 mm), and this far above the head box's bottom,
  // below the ears and above the trapezius of a level head: the wall behind, or hair hanging there.
  std::array<double, 2> beside_neck_out_mm{110.0, 140.0};
  std::array<double, 2> beside_neck_up_mm{25.0, 50.0};
};

// Up to SKIN_REFS_MAX of the samples' chromaticities, chosen farthest first so that every sample lies
// near one, the largest distance of a sample from its nearest chosen one (the spread) and the
// luminance floor (nerf::SkinChroma), and the colours beside the neck (SkinChroma::beside_neck); empty
// when the box has no landmarks or fewer than min_samples patches could be read. Photos without an
// image in memory are read from their path.
nerf::SkinChroma skin_colours(const fit::HeadBox& box, const std::vector<fit::PosedPhoto>& photos,
                              const SkinSampleOptions& options = {});

}  // namespace lorgnette::capture
