// Held-out views rendered by the marcher, and their metrics (see evaluate.h).
#include "host/render/evaluate.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>

#include "host/dataset/metrics.h"
#include "host/render/renderer.h"
#include "host/util/interrupt.h"

namespace lorgnette::render {

namespace {
// The render already holds the background behind the model: keep its RGB.
Image rgb_of(const Image& rgba) {
  Image out(rgba.width, rgba.height, 3);
  for (size_t i = 0, n = size_t(rgba.width) * rgba.height; i < n; ++i)
    for (int c = 0; c < 3; ++c) out.pixels[3 * i + c] = rgba.pixels[4 * i + c];
  return out;
}
}  // namespace

void write_comparison(const std::string& path, const Image& prediction, const Image& truth) {
  const int w = truth.width, h = truth.height;
  Image sheet(3 * w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        float p = prediction.at(x, y, c), t = truth.at(x, y, c);
        sheet.at(x, y, c) = p;
        sheet.at(w + x, y, c) = t;
        float e = std::min(1.0f, 4.0f * std::fabs(linear_to_srgb(p) - linear_to_srgb(t)));
        sheet.at(2 * w + x, y, c) = srgb_to_linear(e);
      }
  write_image(path, sheet);
}

EvalResult evaluate(nerf::NerfModel& model, const std::vector<nerf::View>& views,
                    const EvalOptions& options) {
  if (views.empty()) throw std::runtime_error("nothing to evaluate: the evaluation split has no views");
  auto start = std::chrono::steady_clock::now();
  size_t n = options.max_views ? std::min<size_t>(options.max_views, views.size()) : views.size();
  if (!options.output_dir.empty()) std::filesystem::create_directories(options.output_dir);
  EvalResult r;
  Renderer renderer(model.runtime());
  RenderOptions ro;
  ro.background = options.background;
  for (size_t k = 0; k < n; ++k) {
    size_t i = k * views.size() / n;
    const nerf::View& v = views[i];
    // A stop request ends the evaluation at the next view; the images written so far are whole files.
    if (interrupted()) throw std::runtime_error("interrupted: the evaluation stopped before its scores");
    if (!v.image) throw std::runtime_error(fmt::format("evaluation view {} has no image", i));
    Image pred = rgb_of(renderer.render(model, v.camera, nullptr, ro).rgba);
    Image truth = dataset::composite_over(*v.image, options.background);
    r.view_psnr.push_back(dataset::psnr(pred, truth));
    r.view_ssim.push_back(dataset::ssim(pred, truth));
    spdlog::debug("view {}: PSNR {:.2f} dB, SSIM {:.4f}", i, r.view_psnr.back(), r.view_ssim.back());
    if (!options.output_dir.empty())
      write_comparison(fmt::format("{}/{:03d}_pred_truth_error.png", options.output_dir, i), pred, truth);
  }
  r.views = static_cast<uint32_t>(n);
  for (size_t k = 0; k < n; ++k) {
    r.psnr += r.view_psnr[k] / double(n);
    r.ssim += r.view_ssim[k] / double(n);
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace lorgnette::render
