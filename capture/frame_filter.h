// Frame selection for captures: drops blurred frames (variance of the Laplacian, relative to the
// neighbouring frames, so a slow, evenly soft capture keeps its frames) and frames with closed eyes
// (eye aspect ratio of the 68-point landmarks, relative to the capture's own open-eye level).
// Neither filter ever drops every frame: a capture that is blurred or closed-eyed throughout is kept
// and a warning says so. Decisions carry a reason per dropped frame for the report.
#pragma once
#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

namespace lorgnette::capture {

struct FilterDecision {
  std::vector<bool> keep;            // one per frame
  std::vector<std::string> reasons;  // why each dropped frame was dropped ("" when kept)
  std::vector<std::string> warnings;
  size_t dropped() const;
};

// Variance of the 3x3 Laplacian of the grey image (8-bit scale), the usual focus measure.
double laplacian_variance(const cv::Mat& image);

struct BlurOptions {
  int half_window = 3;       // neighbours on each side that define the local sharpness level
  double ratio = 0.6;        // drop frames sharper than less than this fraction of the local median
  double blurred_below = 8;  // warn when the capture's median sharpness is below this (8-bit grey)
};
FilterDecision blur_filter(const std::vector<double>& sharpness, const BlurOptions& options = {});

// Eye aspect ratio (Soukupova & Cech 2016) of one eye's six landmarks p1..p6 in dlib's order
// (36..41 or 42..47): (|p2 - p6| + |p3 - p5|) / (2 |p1 - p4|). About 0.3 open, below 0.2 closed.
double eye_aspect_ratio(const std::array<Eigen::Vector2d, 6>& eye);

struct BlinkOptions {
  double closed_below = 0.2;  // absolute EAR under which eyes count as closed...
  double relative = 0.75;     // ...and below this fraction of the capture's median EAR
};
// ear[i]: mean EAR of both eyes of frame i, or nullopt where no face was found (kept).
FilterDecision blink_filter(const std::vector<std::optional<double>>& ear, const BlinkOptions& options = {});

}  // namespace lorgnette::capture
