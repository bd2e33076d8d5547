// The card's ignore regions; see card_ignore.h.
#include "capture/card_ignore.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <map>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "capture/card_fingers.h"
#include "fit/camera_math.h"

namespace lorgnette::capture {
namespace {

using V2 = Eigen::Vector2d;
using V3 = Eigen::Vector3d;

// The card's side lengths in millimetres along its corner order: (corner 0 -> 1, corner 1 -> 2).
std::pair<double, double> card_sides_mm(const std::array<V3, 4>& c) {
  const bool first_long =
      (c[1] - c[0]).norm() + (c[3] - c[2]).norm() > (c[2] - c[1]).norm() + (c[0] - c[3]).norm();
  return first_long ? std::make_pair(kCardWidthMm, kCardHeightMm)
                    : std::make_pair(kCardHeightMm, kCardWidthMm);
}

// A frame's own corners (card order) grown by `margin` mm through the homography from the card's
// millimetres to the image: perspective-correct without the frame's pose.
dataset::IgnorePolygon grown_from_corners(const std::array<V2, 4>& corners, std::pair<double, double> sides,
                                          double margin) {
  const auto [a, b] = sides;
  const cv::Point2f card[4] = {{0, 0}, {float(a), 0}, {float(a), float(b)}, {0, float(b)}};
  cv::Point2f image[4];
  for (int k = 0; k < 4; ++k) image[k] = cv::Point2f(float(corners[k].x()), float(corners[k].y()));
  const cv::Mat h = cv::getPerspectiveTransform(card, image);
  const float m = float(margin);
  std::vector<cv::Point2f> grown = {{-m, -m},
                                    {float(a) + m, -m},
                                    {float(a) + m, float(b) + m},
                                    {-m, float(b) + m}},
                           out;
  cv::perspectiveTransform(grown, out, h);
  dataset::IgnorePolygon poly;
  for (const auto& p : out) poly.emplace_back(p.x, p.y);
  return poly;
}

// The triangulated card's corners in `cam`'s pixels; nothing when one lies behind the camera.
std::optional<std::array<V2, 4>> projected_corners(const Camera& cam, const std::array<V3, 4>& c) {
  std::array<V2, 4> uv;
  for (int k = 0; k < 4; ++k)
    if (!fit::camera_project(cam, c[size_t(k)], &uv[size_t(k)])) return std::nullopt;
  return uv;
}

// The card's face in `grey` (the frame's image at any size) resampled onto the card's millimetres at
// kPatchMmPerPx, its outer pixels cut off (they mix the card's edge with what lies behind it).
constexpr double kPatchMmPerPx = 2.0;
cv::Mat card_patch(const cv::Mat& grey, const Camera& cam, const std::array<V2, 4>& corners,
                   std::pair<double, double> sides) {
  const int w = std::max(8, int(std::lround(sides.first / kPatchMmPerPx)));
  const int h = std::max(8, int(std::lround(sides.second / kPatchMmPerPx)));
  const double sx = double(grey.cols) / double(cam.width), sy = double(grey.rows) / double(cam.height);
  // OpenCV puts pixel centres at integers, the dataset at i + 0.5.
  const cv::Point2f patch[4] = {{-0.5f, -0.5f}, {w - 0.5f, -0.5f}, {w - 0.5f, h - 0.5f}, {-0.5f, h - 0.5f}};
  cv::Point2f image[4];
  for (int k = 0; k < 4; ++k)
    image[k] = cv::Point2f(float(corners[k].x() * sx - 0.5), float(corners[k].y() * sy - 0.5));
  cv::Mat out;
  cv::warpPerspective(grey, out, cv::getPerspectiveTransform(patch, image), cv::Size(w, h),
                      cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REPLICATE);
  out.convertTo(out, CV_32F);
  return out(cv::Rect(2, 2, w - 4, h - 4)).clone();
}

// Zero-mean normalised cross-correlation; 0 when either patch is flat.
double ncc(const cv::Mat& a, const cv::Mat& b) {
  cv::Scalar ma, sa, mb, sb;
  cv::meanStdDev(a, ma, sa);
  cv::meanStdDev(b, mb, sb);
  if (sa[0] < 1.0 || sb[0] < 1.0) return 0.0;
  return cv::mean((a - ma[0]).mul(b - mb[0]))[0] / (sa[0] * sb[0]);
}

// Per-pixel median of the measured frames' card patches: the card's face without the fingers that
// cover it in some of them.
cv::Mat reference_patch(const std::vector<cv::Mat>& patches) {
  cv::Mat ref(patches[0].size(), CV_32F);
  std::vector<float> v(patches.size());
  for (int y = 0; y < ref.rows; ++y)
    for (int x = 0; x < ref.cols; ++x) {
      for (size_t i = 0; i < patches.size(); ++i) v[i] = patches[i].at<float>(y, x);
      std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
      ref.at<float>(y, x) = v[v.size() / 2];
    }
  return ref;
}

// Whether the triangulated card, projected into a frame it was not measured in, has the card's face
// there: its patch correlates with the measured frames' (printing, logo, edges) at least as much as
// options.min_likeness. A frame whose card lies behind its camera or outside its image does not.
bool shows_card(const cv::Mat& grey, const CardView& v, const CardScale& card, const cv::Mat& reference,
                std::pair<double, double> sides, const CardIgnoreOptions& options) {
  const auto projected = projected_corners(v.camera, card.corners);
  if (!projected) return false;
  const std::array<V2, 4>& uv = *projected;
  for (const V2& p : uv)
    if (p.x() < 0 || p.y() < 0 || p.x() > v.camera.width || p.y() > v.camera.height) return false;
  const double likeness = ncc(card_patch(grey, v.camera, uv, sides), reference);
  spdlog::debug("card: frame '{}' outside the measured ones: likeness {:.2f} to the card's face", v.name,
                likeness);
  return likeness >= options.min_likeness;
}

}  // namespace

std::vector<dataset::FrameIgnore> card_ignore_regions(const std::vector<CardView>& views,
                                                      const std::vector<cv::Mat>& greys,
                                                      const CardScale& card,
                                                      const CardIgnoreOptions& options) {
  std::vector<dataset::FrameIgnore> regions;
  if (!card.found || card.frame_names.empty()) return regions;
  std::map<std::string, size_t> seen;  // frame name -> index in card.frame_names
  for (size_t j = 0; j < card.frame_names.size(); ++j) seen[card.frame_names[j]] = j;
  int first = -1, last = -1;
  std::vector<cv::Mat> measured;
  const auto sides = card_sides_mm(card.corners);
  for (int i = 0; i < int(views.size()); ++i) {
    auto it = seen.find(views[size_t(i)].name);
    if (it == seen.end()) continue;
    last = i, first = first < 0 ? i : first;
    if (!greys.empty())
      measured.push_back(
          card_patch(greys[size_t(i)], views[size_t(i)].camera, card.frame_corners[it->second], sides));
  }
  const cv::Mat reference = measured.empty() ? cv::Mat() : reference_patch(measured);
  for (int i = 0; i < int(views.size()); ++i) {
    const CardView& v = views[size_t(i)];
    std::optional<std::array<V2, 4>> corners;
    if (auto it = seen.find(v.name); it != seen.end())
      corners = card.frame_corners[it->second];
    else if ((first < i && i < last) ||
             (!reference.empty() && shows_card(greys[size_t(i)], v, card, reference, sides, options)))
      corners = projected_corners(v.camera, card.corners);
    if (!corners) continue;
    dataset::FrameIgnore f{v.name, int(v.camera.width), int(v.camera.height), {}};
    f.polygons.push_back(grown_from_corners(*corners, sides, options.margin_mm));
    if (!greys.empty())
      for (auto& strip : finger_strips(greys[size_t(i)], f.width, f.height, *corners, sides, options.fingers))
        f.polygons.push_back(std::move(strip));
    spdlog::debug("card: frame '{}' ignores the card and {} finger strips", v.name, f.polygons.size() - 1);
    regions.push_back(std::move(f));
  }
  return regions;
}

}  // namespace lorgnette::capture
