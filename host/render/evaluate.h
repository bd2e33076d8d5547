// Evaluation of a trained model on held-out views: each view is rendered by the compositing marcher
// (renderer.h, the same renderer `render`, `fit` and the demo use: empty-space skipping and early
// termination, so mask-less captures are not slow), then PSNR and SSIM per view
// (host/dataset/metrics.h, on sRGB values as the NeRF papers) and optional prediction | truth |
// error images.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "host/nerf/model.h"
#include "host/nerf/views.h"
#include "host/util/image_io.h"

namespace lorgnette::render {

struct EvalOptions {
  std::array<float, 3> background{1.0f, 1.0f, 1.0f};  // linear RGB behind the model and the truth
  uint32_t max_views = 0;                             // > 0: evaluate at most this many views, evenly spaced
  std::string output_dir;  // "" = no images; else <dir>/<index>_pred_truth_error.png
};

struct EvalResult {
  double psnr = 0.0, ssim = 0.0;  // means over the views
  uint32_t views = 0;
  std::vector<double> view_psnr, view_ssim;
  double seconds = 0.0;
};

// views: held-out views with RGBA truth images (composited over the render background).
EvalResult evaluate(nerf::NerfModel& model, const std::vector<nerf::View>& views,
                    const EvalOptions& options = {});

// prediction | truth | error (|difference| x 4, sRGB) side by side, written as PNG.
void write_comparison(const std::string& path, const Image& prediction, const Image& truth);

}  // namespace lorgnette::render
