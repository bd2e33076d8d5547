// Image quality metrics for evaluation, in the convention of the NeRF papers (NeRF, Mip-NeRF,
// Instant-NGP): both images are compared as sRGB-encoded values in [0, 1] (our Images are linear, so
// they are encoded with linear_to_srgb, which clamps to [0, 1] first), over the RGB channels only.
// - PSNR = 10 log10(1 / MSE), MSE averaged over all pixels and the three channels; +inf for identical
//   images.
// - SSIM (Wang, Bovik, Sheikh, Simoncelli 2004): 11x11 Gaussian window with sigma 1.5, K1 = 0.01,
//   K2 = 0.03, dynamic range L = 1; the SSIM map is computed where the window fits entirely inside the
//   image ("valid" filtering, as the reference MATLAB code and Mip-NeRF's compute_ssim do), averaged
//   over that map and then over the three channels.
// RGBA inputs must be composited first (composite_over): the alpha channel is not compared.
#pragma once
#include <array>

#include "host/util/image_io.h"

namespace lorgnette::dataset {

// Mean squared error of the sRGB-encoded RGB values. Throws when sizes differ or an image has fewer
// than 3 channels.
double mse_srgb(const Image& prediction, const Image& truth);
double psnr(const Image& prediction, const Image& truth);
// Throws when the images are smaller than the 11x11 window.
double ssim(const Image& prediction, const Image& truth);

// Linear RGB over a constant linear background: rgb * a + bg * (1 - a). 3-channel input is returned
// unchanged (as 3 channels); the result has 3 channels.
Image composite_over(const Image& rgba, const std::array<float, 3>& background);

}  // namespace lorgnette::dataset
