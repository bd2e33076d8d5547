// Haze is not a head (#41). A NeRF leaves haze around a real capture: room haze beside the head, the
// soft sides of a frontal capture that saw them only at grazing angles. Haze can be denser than the
// contact's solid threshold point by point (place.h) and yet hide little of what lies behind it; a
// temple probed against it spreads as if the head were wider than any head (#41: 20 and 16.5 deg on a
// selfie whose temples lay on room haze).
// The fit's other surfaces are already read where a ray's opacity reaches 0.5 (the nose point, the
// temples, fit.h): the head is what a render shows as solid. So here: a dense point is part of the
// head only when the opacity in front of it, seen from outside along the horizontal line from the
// head's vertical axis out through it (as a temple meets it), reaches kHeadOpacity within
// kOpacityReachMm. Skin under hair keeps its hair in front and stays solid; a point inside haze that
// does not add up to that opacity does not.
#pragma once
#include "fit/head_probe.h"

namespace lorgnette::fit {

// The opacity a render shows as solid (the fit's surface level, fit.h's nose_opacity).
constexpr double kHeadOpacity = 0.5;
// How far outside a point its opacity is summed: the soft sides of a room capture build their opacity
// up over 10-20 mm (docs/fit.md, section 5); 20 mm holds them and stays inside a temple's reach.
constexpr double kOpacityReachMm = 20.0;
constexpr double kOpacityStepMm = 1.0;  // sampling of that sum (a NeRF's step is 1-2 mm on a head)

// `value`'s density where `head.density` is above the probe's solid threshold and the opacity of
// `head.density` in front of the point reaches kHeadOpacity; 0 elsewhere. `value` is the density a
// caller judges (e.g. with hair removed); `head.density` is the one that hides (hair included).
DensityFn density_behind_opacity(const HeadProbe& head, DensityFn value);

}  // namespace lorgnette::fit
