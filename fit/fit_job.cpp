// The fit on a NeRF as one job (see fit_job.h).
#include "fit/fit_job.h"

#include <filesystem>

#include "host/util/bounds.h"

namespace lorgnette::fit {

FitJobResult run_fit_job(nerf::NerfModel& model, const GlassesInput& glasses, const FitOptions& options,
                         const NerfViewOptions& views) {
  std::string transforms = views.dataset.empty() ? model.metadata.dataset_path : views.dataset;
  if (!transforms.empty() && std::filesystem::is_directory(transforms)) transforms += "/transforms.json";
  NerfViewSource source(model, prior_from_transforms(transforms, model), views.render);
  FitJobResult job;
  FitOptions opt = options;
  if (const auto& m = model.metadata.metric_scale; m && !opt.scale.card)
    opt.scale.card = CaptureScale{m->source, m->mm_per_unit, m->uncertainty};
  job.fit = fit_glasses(source, glasses, opt);
  if (!model.metadata.subject_problem.empty()) {  // a head in a room: never a good fit (#13)
    job.fit.ok = false;
    job.fit.warnings.push_back("the model was trained without separating the subject: " +
                               model.metadata.subject_problem);
  }
  job.placement = make_placement_file(job.fit, glasses.path, scale_policy_name(job.fit.scale_policy));
  return job;
}

FitJobResult run_fit_job(nerf::NerfModel& model, const std::string& glasses_path, const FitOptions& options,
                         const NerfViewOptions& views) {
  return run_fit_job(model, load_glasses_input(glasses_path), options, views);
}

// The table's ranges (host/util/bounds.h): `fit`, Python's fit() and the service's fits check the
// same numbers before minutes of rendering.
void validate(const FitSettings& s) {
  check_bound(bounds::kFitViews, s.views);
  check_bound(bounds::kFitYawRange, s.yaw_range_deg);
  check_bound(bounds::kFitPitchRange, s.pitch_range_deg);
  check_bound(bounds::kFitResolution, s.resolution);
  check_bound_or_zero(bounds::kFitCapResolution, s.cap_resolution);
  check_bound(bounds::kFitUpsample, s.upsample);
}

FitOptions fit_options(const FitSettings& s) {
  validate(s);
  FitOptions opt;
  opt.cap.views = s.views;
  opt.cap.yaw_range_deg = s.yaw_range_deg;
  opt.cap.pitch_range_deg = s.pitch_range_deg;
  opt.front.width = opt.front.height = s.resolution;
  opt.cap.size = s.cap_resolution;
  opt.detection.detector.upsample = s.upsample;
  if (!s.landmark_model.empty()) opt.detection.detector.model_path = s.landmark_model;
  if (!s.mean_face.empty()) opt.head.mean_face_path = s.mean_face;
  opt.place.scale_policy = parse_scale_policy(s.policy);
  opt.debug_dir = s.debug_dir;
  return opt;
}

}  // namespace lorgnette::fit
