// The fit as one job on a trained NeRF: the view prior from the capture's cameras, the NeRF as the
// ViewSource, fit_glasses and the placement.json it gives. `lorgnette fit`, the demo, the viewer,
// the Python module and the NeRF benchmarks all run this; fit_glasses (fit.h) stays the entry for
// other ViewSources (the mesh in tests and benchmarks).
#pragma once
#include <string>

#include "fit/fit.h"
#include "fit/fit_placement.h"
#include "fit/glasses_input.h"
#include "fit/nerf_view_source.h"
#include "fit/placement_json.h"

namespace lorgnette::fit {

// Where the NeRF's views come from.
struct NerfViewOptions {
  // The capture's transforms.json (or its folder) for the prior front and up; empty: the dataset the
  // model was trained on (its metadata), when it is still there.
  std::string dataset;
  // The views' marcher (NerfViewSource): NeRF step x1.5. The views only feed the detector, and at
  // x1.5 the fit stays within its targets (nose 2 mm, ears 4 mm, rotation 2 deg) at about 0.75x the
  // time of step x1 (docs/fit.md, "The cap of views").
  render::RenderOptions render = views_render_options();
  static render::RenderOptions views_render_options() {
    render::RenderOptions o;
    o.step_scale = 1.5f;
    return o;
  }
};

// The settings a user chooses (the `lorgnette fit` flags, the Python fit() arguments), with the
// CLI's defaults; fit_options() turns them into FitOptions so every front end fits alike.
struct FitSettings {
  int views = 12, resolution = 384, upsample = 0;
  int cap_resolution = 256;  // the K views' size (CapOptions::size); `resolution` is the front search's
  double yaw_range_deg = 20.0, pitch_range_deg = 15.0;
  std::string policy = "auto", landmark_model, mean_face, debug_dir;
};
// Throws OutOfRange for a number outside host/util/bounds.h's range.
void validate(const FitSettings& settings);
// Validates, then throws on an unknown policy.
FitOptions fit_options(const FitSettings& settings);

struct FitJobResult {
  FitResult fit;
  PlacementFile placement;  // make_placement_file: the glasses' path and the scale policy the fit used
};

// Throws what fit_glasses throws. Writes nothing (write_placement is the caller's).
FitJobResult run_fit_job(nerf::NerfModel& model, const GlassesInput& glasses, const FitOptions& options,
                         const NerfViewOptions& views = {});

// The same after loading the glasses file (load_glasses_input).
FitJobResult run_fit_job(nerf::NerfModel& model, const std::string& glasses_path, const FitOptions& options,
                         const NerfViewOptions& views = {});

}  // namespace lorgnette::fit
