// A fit's result as placement.json's contents (see fit_placement.h).
#include "fit/fit_placement.h"

namespace lorgnette::fit {

PlacementFile make_placement_file(const FitResult& r, const std::string& glasses_path,
                                  const std::string& policy) {
  PlacementFile p;
  p.glasses_path = glasses_path;
  if (!glasses_path.empty()) p.glasses_hash = file_hash(glasses_path);
  p.transform = r.placement.transform;
  p.scale_policy = policy;
  p.scale = r.placement.scale;
  p.mm_per_unit = r.head.mm_per_unit;
  p.pd_mm = r.head.pd_mm;
  p.scale_source = scale_source_name(r.scale.source);
  p.mm_per_unit_uncertainty = r.scale.mm_per_unit_uncertainty;
  p.pd_uncertainty_mm = r.pd_uncertainty_mm;
  p.has_advice = !r.advice.rules.empty();
  p.advice = r.advice;
  for (const auto& [name, l] : r.landmarks) {
    p.landmarks[name] = {l.position, l.sigma_mm, l.views};
    p.residuals_px[name] = l.residual_px;
  }
  p.views_used = r.views_used;
  p.views_total = int(r.views.size());
  p.penetration_mm = r.contact.penetration_mm;
  p.contact_shift_mm = r.contact.shift_mm;
  p.contact_rise_mm = r.contact.rise_mm;
  p.front_penetration_mm = r.contact.front_penetration_mm;
  p.tip_penetration_mm = r.contact.tip_penetration_mm;
  p.seconds = r.seconds;
  p.warnings = r.warnings;
  p.ok = r.ok;
  p.has_temples = r.temples.fitted;
  p.temples = r.temples;
  for (const InputCheck& c : r.checks) {
    nlohmann::json e = {{"checked", c.checked}, {"passed", c.passed}, {"value", c.value}, {"limit", c.limit}};
    if (!c.reason.empty()) e["reason"] = c.reason;
    p.checks[c.name] = e;
  }
  return p;
}

}  // namespace lorgnette::fit
