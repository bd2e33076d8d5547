// The fit on a NeRF as one job (see fit_job.h).
#include "fit/fit_job.h"

#include <filesystem>

namespace lorgnette::fit {

FitJobResult run_fit_job(nerf::NerfModel& model, const GlassesInput& glasses, const FitOptions& options,
                         const NerfViewOptions& views) {
  std::string transforms = views.dataset.empty() ? model.metadata.dataset_path : views.dataset;
  if (!transforms.empty() && std::filesystem::is_directory(transforms)) transforms += "/transforms.json";
  NerfViewSource source(model, prior_from_transforms(transforms, model), views.render);
  FitJobResult job;
  FitOptions opt = options;
  if (const auto& m = model.metadata.metric_scale; m && !opt.scale.card)
    opt.scale.card = CaptureScale{m->source, m->mm_per_unit, m->mm_per_unit_uncertainty};
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

FitOptions fit_options(const FitSettings& s) {
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
