// The ear rests found on the head's density (docs/fit.md, "The ear search"): where a temple arm
// lowered onto the side of the head comes to rest on the ear's root, the crease between the skull
// and the top of the ear (the otobasion superius; synth's `ear_rest_l/r`). Eq. 2-3 (ears.h) estimate
// the ear from the temple landmark, the eye height and half the eye-corner distance back; with dlib's
// temples that lands 20-40 mm off the ear, so the fit uses the density's rests wherever it shows them.
//
// The search has three parts, each in a file of its own: the ray field (ear_rays.h), the line finder
// (ear_lines.h: the crease at each depth, the lines they trace, each line's rest) and the pairing
// (ear_pairing.h: which lines of the two sides the fit uses). Where hair covers the ear, the capture
// never saw it, or the window holds no crease, a side is not found; the other side's rest is mirrored
// or Eq. 2-3's ears stand.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "fit/ear_lines.h"
#include "fit/ear_pairing.h"
#include "fit/ear_rays.h"
#include "fit/ears.h"
#include "fit/head_probe.h"

namespace lorgnette::fit {

struct EarRootOptions {
  bool enabled = true;
  EarRayOptions rays;       // the window, the steps and the opacity where a ray meets the head
  EarCreaseOptions crease;  // what counts as the crease between skull and ear at one depth
  EarLineOptions line;      // lines of creases across depths and their rests
  EarPairOptions pair;      // which lines of the two sides the fit uses
};

// One depth's profile: the ray field's heights (mm above the side's outer eye corner; NaN where the ray
// met nothing) across the window at `depth_mm`. What the search reads for its creases, for charts.
struct EarRootProfile {
  double depth_mm = 0.0;  // along d_fwd from the temple landmark
  std::vector<double> lateral_mm, height_mm;
};
std::vector<EarRootProfile> ear_root_profiles(const DensityFn& density, const EarRootInputs& in,
                                              const EarRootOptions& options,
                                              const std::vector<double>& depths_mm);

// Every line of creases at least `min_slices` long on one side, ordered (ear_lines.h), each with its
// rest; or one side not found, saying what the window showed. Throws std::invalid_argument on bad
// inputs (check_ear_search).
std::vector<EarRootSide> find_ear_root_lines(const DensityFn& density, const EarRootInputs& in,
                                             const EarRootOptions& options);
// The first of them: the rest on the highest line.
EarRootSide find_ear_root(const DensityFn& density, const EarRootInputs& in, const EarRootOptions& options);

struct EarRoots {
  EarRootSide left, right;
  // Which ears `apply_ear_roots` put in place: Eq. 2-3's, both sides' rests, or one side's mirrored.
  enum class Use { kEq23, kBoth, kMirrored } use = Use::kEq23;
  bool from_density() const { return use != Use::kEq23; }
  std::string note;             // which pairing rules changed the first lines' result, and why
  std::string summary() const;  // for the log: what each side showed and which ears were used
};

// Both sides' searches on `ears`' inputs and the pairing rules (ear_pairing.h) in order: each side's
// lines that the veto accepts (rule 1); a pair that agrees where the first lines do not (2); both rests
// at one height (3); then both at their shared height and depth (4, 5), or, when one side alone is
// found and no higher than plausible_highest_mm, that rest mirrored onto the other side (6: the other
// showed no ear, or was vetoed by the veto the found side passed). Otherwise `ears` stays as it is.
EarRoots apply_ear_roots(const DensityFn& density, const EarInputs& in, const Eigen::Vector3d& d_eye,
                         double mm_per_unit, const EarRootOptions& options, EarPoints& ears,
                         const EarVeto& accept = {});

}  // namespace lorgnette::fit
