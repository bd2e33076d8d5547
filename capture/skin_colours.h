// The subject's skin colours from its training photos, for the room-explained clearing in the neck's
// keep zone (host/nerf/background_field.h, BackgroundOptions::neck_clear): the face is sampled at
// points placed by its triangulated landmarks (both cheeks below the eyes and the chin below the lower
// lip: bare skin on nearly every face, away from the eyes, brows, lips, nostrils and the highlights a
// forehead and a nose take), in every photo that sees the face within 35 deg of its front.
#pragma once
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
};

// Up to SKIN_REFS_MAX of the samples' chromaticities, chosen farthest first so that every sample lies
// near one, the largest distance of a sample from its nearest chosen one (the spread) and the
// luminance floor (nerf::SkinChroma); empty when the box has no landmarks or fewer than min_samples
// patches could be read. Photos without an image in memory are read from their path.
nerf::SkinChroma skin_colours(const fit::HeadBox& box, const std::vector<fit::PosedPhoto>& photos,
                              const SkinSampleOptions& options = {});

}  // namespace lorgnette::capture
