// Hair is not skin (issue 13, item 5): the temples of real glasses slide under the hair and rest on
// the ear, but a NeRF reconstructs hair as dense volume, and a temple probed against it spreads to
// its limit and still "passes into the head" (a long-haired capture: 9.25 mm at 25 deg). Hair is told
// from skin by colour: the skin's tone is read where the face is certainly skin (the nose line,
// dlib 27-30) and a dense point much darker than that is hair. The temple stage then probes a
// density with hair removed; the front (rims, bridge, pads) keeps the full density. Blond or grey
// hair as bright as the skin still counts as solid (the fit then spreads the temples as before): a
// miss that keeps the temples out of the skin rather than one that lets them into it.
#pragma once
#include <Eigen/Core>
#include <functional>
#include <optional>
#include <vector>

#include "fit/head_probe.h"

namespace lorgnette::fit {

// Linear RGB at scene points seen along unit directions (ViewSource::colour); empty when unknown.
using ColourFn = std::function<std::vector<Eigen::Vector3f>(const std::vector<Eigen::Vector3f>& points,
                                                            const std::vector<Eigen::Vector3f>& dirs)>;

struct HairOptions {
  bool enabled = true;
  // A dense point darker than this times the skin's luminance is hair. Measured (linear Rec. 709
  // luminance over the skin's, the skin from the nose line): in2n-face's dense volume along the
  // right temple, the hair over the ear, median 0.02, 90 % below 0.08; the face's shaded sides (jaw
  // contour, both captures) 0.26-0.99 where not bearded. 0.15 is the geometric middle of 0.08 and
  // 0.26.
  double max_luminance_ratio = 0.15;
};

struct SkinTone {
  Eigen::Vector3f rgb = Eigen::Vector3f::Zero();  // linear, the sample of median luminance
  double luminance = 0.0;                         // Rec. 709 luminance of rgb
  int samples = 0;
};

double luminance(const Eigen::Vector3f& linear_rgb);

// The skin's tone from points on the face's skin seen along `view_dir`: the sample of median
// luminance (robust to a landmark that landed on an eyebrow or a nostril). nullopt when the source
// has no colour, there are no points, or the median is black (nothing to compare hair with).
std::optional<SkinTone> skin_tone(const ColourFn& colour, const std::vector<Eigen::Vector3d>& skin_points,
                                  const Eigen::Vector3d& view_dir);

// An ear's top seen from above (along -`up`): per depth the brightest of its points across the top's
// width, then the median over the depths (the upper one of an even count). Hair hanging over the
// ear's root darkens the top's inner edge only, and at some depths; an ear under hair is dark across
// its top at most depths. nullopt when the source has no colour or there are no points.
std::optional<double> ear_top_luminance(const ColourFn& colour,
                                        const std::vector<std::vector<Eigen::Vector3d>>& top_per_depth,
                                        const Eigen::Vector3d& up);

// `head`'s density with hair removed: a point denser than the probe's contact threshold whose
// colour, seen horizontally towards the head's vertical axis (from outside, as a temple meets it),
// has less than max_luminance_ratio x the skin's luminance counts as empty. Colour is queried only
// for the dense points.
DensityFn density_without_hair(const HeadProbe& head, ColourFn colour, const SkinTone& skin,
                               const HairOptions& options);

}  // namespace lorgnette::fit
