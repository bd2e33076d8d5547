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
  job.fit = fit_glasses(source, glasses, options);
  job.placement = make_placement_file(job.fit, glasses.path, scale_policy_name(options.place.scale_policy));
  return job;
}

FitJobResult run_fit_job(nerf::NerfModel& model, const std::string& glasses_path, const FitOptions& options,
                         const NerfViewOptions& views) {
  return run_fit_job(model, load_glasses_input(glasses_path), options, views);
}

}  // namespace lorgnette::fit
