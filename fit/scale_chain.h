// Which metric scale the fit uses, best source first, each with a 1-sigma uncertainty:
//   1. a card the capture found and triangulated (the model's header, metadata.metric_scale): its
//      edges are known to 0.1 mm, so its own stated uncertainty holds;
//   2. the irises (iris.h): 11.7 mm +- 0.5 mm across adults, about 4 % of the scale;
//   3. the mean face aligned to the landmarks (head_frame.h): faces differ in size by more than
//      irises do (the demo head: +7.2 %), so it is called approximate with a 10 % uncertainty.
// The scale policy "auto" then shows the frame at its true size when the scale is metric (card or
// irises) and stretches it to the temples with the mean face, whose sizes are not real.
#pragma once
#include <optional>
#include <string>

#include "fit/iris.h"
#include "fit/place.h"

namespace lorgnette::fit {

enum class ScaleSource { kCard, kIris, kMeanFace };
const char* scale_source_name(ScaleSource s);          // "card" | "iris" | "mean-face"
ScaleSource parse_scale_source(const std::string& s);  // throws on anything else

constexpr double kMeanFaceRelativeUncertainty = 0.10;

// The scale a capture measured (a card), in mm per scene unit of the model.
struct CaptureScale {
  std::string source = "card";
  double mm_per_unit = 0.0, mm_per_unit_uncertainty = 0.0;
};

struct MetricScale {
  ScaleSource source = ScaleSource::kMeanFace;
  double mm_per_unit = 0.0, mm_per_unit_uncertainty = 0.0;
  double mean_face_mm_per_unit = 0.0;  // the mean face's figure, kept for comparison
  std::string why;                     // why this source (and why not the better ones)
  double relative_uncertainty() const {
    return mm_per_unit > 0 ? mm_per_unit_uncertainty / mm_per_unit : 0.0;
  }
};

// The card when given, else the irises when they passed, else the mean face. `iris` may be null (not
// measured). Throws when the card's numbers are not positive and finite.
MetricScale choose_scale(const std::optional<CaptureScale>& card, const IrisScale* iris,
                         double mean_face_mm_per_unit);

// "auto": true size with a card or the irises, stretch with the mean face; the others as asked.
ScalePolicy resolve_scale_policy(ScalePolicy requested, ScaleSource source);

// PD's 1-sigma in mm: the scale's share of it and the two eye centres' own positional sigmas.
double pd_uncertainty_mm(double pd_mm, double relative_scale_uncertainty, double eye_sigma_l_mm,
                         double eye_sigma_r_mm);

// One line for a person: where the scale came from, with its and PD's +-, and whether the frame is
// shown at its real size (`policy` as placed: "true-size" or "stretch"). `source` "" (an older
// placement): unknown.
std::string scale_summary(const std::string& source, double mm_per_unit, double mm_per_unit_uncertainty,
                          double pd_mm, double pd_uncertainty_mm, const std::string& policy);

}  // namespace lorgnette::fit
