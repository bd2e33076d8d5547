// Evaluation of a trained model on held-out views: a small inference renderer (the training
// sampler in view mode + Field::forward + the same compositing as training, over the image in
// chunks that fit the field's batch), PSNR and SSIM per view (host/dataset/metrics.h, on sRGB
// values as the NeRF papers), and optional prediction | truth | error images.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "host/nerf/model.h"
#include "host/nerf/views.h"
#include "host/util/image_io.h"

namespace lorgnette::nerf {

struct RenderOptions {
  std::array<float, 3> background{1.0f, 1.0f, 1.0f};  // linear RGB behind the model
  uint32_t max_rays = 1u << 14;                        // rays counted per chunk
};

// RGBA linear image (alpha = opacity) of the model seen from `camera`.
Image render_view(NerfModel& model, const Camera& camera, const RenderOptions& options = {});

struct EvalOptions {
  RenderOptions render;
  uint32_t max_views = 0;   // > 0: evaluate at most this many views, evenly spaced
  std::string output_dir;   // "" = no images; else <dir>/<index>_pred_truth_error.png
};

struct EvalResult {
  double psnr = 0.0, ssim = 0.0;  // means over the views
  uint32_t views = 0;
  std::vector<double> view_psnr, view_ssim;
  double seconds = 0.0;
};

// views: held-out views with RGBA truth images (composited over the render background).
EvalResult evaluate(NerfModel& model, const std::vector<View>& views, const EvalOptions& options = {});

// prediction | truth | error (|difference| x 4, sRGB) side by side, written as PNG.
void write_comparison(const std::string& path, const Image& prediction, const Image& truth);

}  // namespace lorgnette::nerf
