// Blur and blink filters over a whole capture (see frame_filter.h for the rules).
#include "capture/frame_filter.h"

#include <fmt/format.h>

#include <algorithm>
#include <opencv2/imgproc.hpp>

namespace lorgnette::capture {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  auto mid = v.begin() + v.size() / 2;
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2) return *mid;
  return 0.5 * (*mid + *std::max_element(v.begin(), mid));
}

// Never drop everything: a filter that would leave no frame keeps them all and says so.
void keep_all_if_empty(FilterDecision& d, const std::string& what) {
  if (d.keep.empty() || std::count(d.keep.begin(), d.keep.end(), true) > 0) return;
  d.warnings.push_back(fmt::format("every frame looked {}; kept them all", what));
  std::fill(d.keep.begin(), d.keep.end(), true);
  std::fill(d.reasons.begin(), d.reasons.end(), std::string());
}

}  // namespace

size_t FilterDecision::dropped() const { return std::count(keep.begin(), keep.end(), false); }

double laplacian_variance(const cv::Mat& image) {
  cv::Mat grey = image, lap;
  if (image.channels() == 3) cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  if (image.channels() == 4) cv::cvtColor(image, grey, cv::COLOR_BGRA2GRAY);
  cv::Laplacian(grey, lap, CV_64F, 1);
  cv::Scalar mean, stddev;
  cv::meanStdDev(lap, mean, stddev);
  return stddev[0] * stddev[0];
}

FilterDecision blur_filter(const std::vector<double>& sharpness, const BlurOptions& opt) {
  FilterDecision d;
  const int n = static_cast<int>(sharpness.size());
  d.keep.assign(n, true);
  d.reasons.assign(n, "");
  for (int i = 0; i < n; ++i) {
    std::vector<double> window;
    for (int j = std::max(0, i - opt.half_window); j <= std::min(n - 1, i + opt.half_window); ++j)
      window.push_back(sharpness[j]);
    double level = median(window);
    if (window.size() >= 3 && sharpness[i] < opt.ratio * level) {
      d.keep[i] = false;
      d.reasons[i] = fmt::format("blurred: sharpness {:.1f} < {:.2f} x neighbours' median {:.1f}",
                                 sharpness[i], opt.ratio, level);
    }
  }
  double overall = median(sharpness);
  if (n > 0 && overall < opt.blurred_below)
    d.warnings.push_back(fmt::format(
        "the whole capture looks blurred (median sharpness {:.1f} < {:.1f}): frames kept, but poses "
        "and the avatar will suffer; hold the phone steadier or use more light",
        overall, opt.blurred_below));
  keep_all_if_empty(d, "blurred");
  return d;
}

double eye_aspect_ratio(const std::array<Eigen::Vector2d, 6>& e) {
  double width = (e[0] - e[3]).norm();
  if (width <= 0) return 0;
  return ((e[1] - e[5]).norm() + (e[2] - e[4]).norm()) / (2.0 * width);
}

FilterDecision blink_filter(const std::vector<std::optional<double>>& ear, const BlinkOptions& opt) {
  FilterDecision d;
  d.keep.assign(ear.size(), true);
  d.reasons.assign(ear.size(), "");
  std::vector<double> seen;
  for (const auto& e : ear)
    if (e) seen.push_back(*e);
  if (seen.empty()) return d;
  double level = median(seen);
  double threshold = std::min(opt.closed_below, opt.relative * level);
  for (size_t i = 0; i < ear.size(); ++i) {
    if (ear[i] && *ear[i] < threshold) {
      d.keep[i] = false;
      d.reasons[i] = fmt::format("eyes closed: eye aspect ratio {:.3f} < {:.3f}", *ear[i], threshold);
    }
  }
  if (level < opt.closed_below)
    d.warnings.push_back(fmt::format(
        "the eyes look closed in most frames (median eye aspect ratio {:.3f} < {:.2f}): frames kept; "
        "the avatar will have closed eyes",
        level, opt.closed_below));
  keep_all_if_empty(d, "closed-eyed");
  return d;
}

}  // namespace lorgnette::capture
