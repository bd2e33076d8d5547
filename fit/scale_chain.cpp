// The scale's source and uncertainty (see scale_chain.h).
#include "fit/scale_chain.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace lorgnette::fit {

const char* scale_source_name(ScaleSource s) {
  return s == ScaleSource::kCard ? "card" : s == ScaleSource::kIris ? "iris" : "mean-face";
}

ScaleSource parse_scale_source(const std::string& s) {
  for (ScaleSource k : {ScaleSource::kCard, ScaleSource::kIris, ScaleSource::kMeanFace})
    if (s == scale_source_name(k)) return k;
  throw std::runtime_error(fmt::format("unknown scale source '{}': expected card, iris or mean-face", s));
}

MetricScale choose_scale(const std::optional<CaptureScale>& card, const IrisScale* iris,
                         double mean_face_mpu) {
  MetricScale m;
  m.mean_face_mm_per_unit = mean_face_mpu;
  if (card) {
    if (!(card->mm_per_unit > 0.0) || !std::isfinite(card->mm_per_unit) ||
        !(card->mm_per_unit_uncertainty >= 0.0) || !std::isfinite(card->mm_per_unit_uncertainty))
      throw std::runtime_error(fmt::format(
          "the model's metric scale ({}) must have mm_per_unit > 0 and an uncertainty >= 0, found {} +- {}: "
          "re-run `lorgnette capture` on the video",
          card->source, card->mm_per_unit, card->mm_per_unit_uncertainty));
    m.source = ScaleSource::kCard;
    m.mm_per_unit = card->mm_per_unit;
    m.mm_per_unit_uncertainty = card->mm_per_unit_uncertainty;
    m.why = fmt::format("the capture's {}: {:.4g} +- {:.2g} mm per unit", card->source, m.mm_per_unit,
                        m.mm_per_unit_uncertainty);
    return m;
  }
  if (iris && iris->ok) {
    m.source = ScaleSource::kIris;
    m.mm_per_unit = iris->mm_per_unit;
    m.mm_per_unit_uncertainty = iris->mm_per_unit_uncertainty;
    m.why = "no card in the capture; the irises: " + iris->why;
    return m;
  }
  if (!(mean_face_mpu > 0.0) || !std::isfinite(mean_face_mpu))
    throw std::runtime_error(fmt::format("the mean face gave no scale ({} mm per unit)", mean_face_mpu));
  m.source = ScaleSource::kMeanFace;
  m.mm_per_unit = mean_face_mpu;
  m.mm_per_unit_uncertainty = kMeanFaceRelativeUncertainty * mean_face_mpu;
  m.why =
      fmt::format("no card in the capture and no iris scale ({}): the mean face's, approximate (+-{:.0f} %)",
                  iris ? iris->why : "not measured", 100 * kMeanFaceRelativeUncertainty);
  return m;
}

ScalePolicy resolve_scale_policy(ScalePolicy requested, ScaleSource source) {
  if (requested != ScalePolicy::kAuto) return requested;
  return source == ScaleSource::kMeanFace ? ScalePolicy::kStretch : ScalePolicy::kTrueSize;
}

double pd_uncertainty_mm(double pd_mm, double rel, double sigma_l, double sigma_r) {
  return std::sqrt(std::pow(pd_mm * rel, 2) + sigma_l * sigma_l + sigma_r * sigma_r);
}

std::string scale_summary(const std::string& source, double mpu, double mpu_sigma, double pd, double pd_sigma,
                          const std::string& policy) {
  const std::string from = source == "card"        ? "a card"
                           : source == "iris"      ? "the irises"
                           : source == "mean-face" ? "the mean face (approximate)"
                                                   : "an unknown source";
  const std::string shown = policy == "true-size"
                                ? "the frame is shown at its real size"
                                : "the frame is stretched to the face's width: the size shown is "
                                  "not its real size";
  return fmt::format("scale from {}: {:.4g} +- {:.2g} mm per unit; PD {:.1f} +- {:.1f} mm; {}", from, mpu,
                     mpu_sigma, pd, pd_sigma, shown);
}

}  // namespace lorgnette::fit
