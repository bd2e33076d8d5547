// The fit's option variants that bench_fit_nerf compares (fit_nerf_accuracy.cpp): speed options
// (DetectorOptions in fit/landmarks_dlib.h, the cap's views), the jaw contour's and the nose's surface
// depths, the temples' and the ears' rules, each named, with the NeRF views' marching step and early
// termination.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "fit/fit.h"

namespace lorgnette::fit {

struct Variant {
  std::string name;
  std::function<void(FitOptions&)> set;
  float step_scale = 1.0f;         // NeRF marching step multiplier (render::RenderOptions)
  float min_transmittance = 0.0f;  // the views' early termination (0: the renderer's default)
};

// The speed options all off ("baseline", the fit before them); each variant's `set` starts from here.
void plain(FitOptions& o);

// Every variant, in the order the bench lists them.
const std::vector<Variant>& all_variants();

}  // namespace lorgnette::fit
