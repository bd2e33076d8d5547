// PSNR and SSIM on sRGB-encoded values; see metrics.h for the conventions. Plain separable
// filtering in double precision (the tests check it against an OpenCV filter2D implementation).
#include "host/dataset/metrics.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace lorgnette::dataset {
namespace {

constexpr int kWindow = 11;
constexpr double kSigma = 1.5, kC1 = 0.01 * 0.01, kC2 = 0.03 * 0.03;

void check_pair(const Image& a, const Image& b, const char* what) {
  if (a.width != b.width || a.height != b.height)
    throw std::runtime_error(fmt::format("{}: images differ in size ({}x{} vs {}x{})", what, a.width,
                                         a.height, b.width, b.height));
  if (a.channels < 3 || b.channels < 3 || a.empty())
    throw std::runtime_error(
        fmt::format("{}: needs RGB images (got {} and {} channels)", what, a.channels, b.channels));
}

// One channel as sRGB-encoded doubles, row-major.
std::vector<double> srgb_plane(const Image& img, int channel) {
  std::vector<double> out(static_cast<size_t>(img.width) * img.height);
  for (size_t p = 0; p < out.size(); ++p) out[p] = linear_to_srgb(img.pixels[p * img.channels + channel]);
  return out;
}

std::vector<double> gaussian_weights() {
  std::vector<double> w(kWindow);
  double sum = 0;
  for (int i = 0; i < kWindow; ++i) sum += w[i] = std::exp(-0.5 * std::pow((i - kWindow / 2) / kSigma, 2));
  for (double& v : w) v /= sum;
  return w;
}

// "Valid" separable Gaussian filter: output is (w - 10) x (h - 10).
std::vector<double> filter_valid(const std::vector<double>& in, int w, int h, const std::vector<double>& g) {
  int ow = w - kWindow + 1, oh = h - kWindow + 1;
  std::vector<double> tmp(static_cast<size_t>(ow) * h), out(static_cast<size_t>(ow) * oh);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < ow; ++x) {
      double s = 0;
      for (int k = 0; k < kWindow; ++k) s += g[k] * in[static_cast<size_t>(y) * w + x + k];
      tmp[static_cast<size_t>(y) * ow + x] = s;
    }
  for (int y = 0; y < oh; ++y)
    for (int x = 0; x < ow; ++x) {
      double s = 0;
      for (int k = 0; k < kWindow; ++k) s += g[k] * tmp[static_cast<size_t>(y + k) * ow + x];
      out[static_cast<size_t>(y) * ow + x] = s;
    }
  return out;
}

double ssim_plane(const std::vector<double>& x, const std::vector<double>& y, int w, int h) {
  static const std::vector<double> g = gaussian_weights();
  std::vector<double> xx(x.size()), yy(x.size()), xy(x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    xx[i] = x[i] * x[i];
    yy[i] = y[i] * y[i];
    xy[i] = x[i] * y[i];
  }
  auto mx = filter_valid(x, w, h, g), my = filter_valid(y, w, h, g);
  auto sxx = filter_valid(xx, w, h, g), syy = filter_valid(yy, w, h, g), sxy = filter_valid(xy, w, h, g);
  double total = 0;
  for (size_t i = 0; i < mx.size(); ++i) {
    double vx = sxx[i] - mx[i] * mx[i], vy = syy[i] - my[i] * my[i], cxy = sxy[i] - mx[i] * my[i];
    total += ((2 * mx[i] * my[i] + kC1) * (2 * cxy + kC2)) /
             ((mx[i] * mx[i] + my[i] * my[i] + kC1) * (vx + vy + kC2));
  }
  return total / mx.size();
}

}  // namespace

double mse_srgb(const Image& prediction, const Image& truth) {
  check_pair(prediction, truth, "mse");
  double sum = 0;
  size_t n = static_cast<size_t>(truth.width) * truth.height;
  for (size_t p = 0; p < n; ++p)
    for (int c = 0; c < 3; ++c) {
      double d = static_cast<double>(linear_to_srgb(prediction.pixels[p * prediction.channels + c])) -
                 linear_to_srgb(truth.pixels[p * truth.channels + c]);
      sum += d * d;
    }
  return sum / (3.0 * n);
}

double psnr(const Image& prediction, const Image& truth) {
  double mse = mse_srgb(prediction, truth);
  return mse == 0 ? std::numeric_limits<double>::infinity() : -10.0 * std::log10(mse);
}

double ssim(const Image& prediction, const Image& truth) {
  check_pair(prediction, truth, "ssim");
  if (truth.width < kWindow || truth.height < kWindow)
    throw std::runtime_error(fmt::format("ssim: images must be at least {}x{} pixels (got {}x{})", kWindow,
                                         kWindow, truth.width, truth.height));
  double sum = 0;
  for (int c = 0; c < 3; ++c)
    sum += ssim_plane(srgb_plane(prediction, c), srgb_plane(truth, c), truth.width, truth.height);
  return sum / 3.0;
}

Image composite_over(const Image& rgba, const std::array<float, 3>& background) {
  if (rgba.channels < 3) throw std::runtime_error("composite_over: needs an RGB or RGBA image");
  Image out(rgba.width, rgba.height, 3);
  size_t n = static_cast<size_t>(rgba.width) * rgba.height;
  for (size_t p = 0; p < n; ++p) {
    float a = rgba.channels >= 4 ? rgba.pixels[p * rgba.channels + 3] : 1.0f;
    for (int c = 0; c < 3; ++c)
      out.pixels[p * 3 + c] = rgba.pixels[p * rgba.channels + c] * a + background[c] * (1.0f - a);
  }
  return out;
}

}  // namespace lorgnette::dataset
