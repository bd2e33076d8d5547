// Fingers over the card's edges; see card_fingers.h.
#include "capture/card_fingers.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>

namespace lorgnette::capture {
namespace {

using V2 = Eigen::Vector2d;
constexpr int kBorderMm = 8;  // the warp covers the card and this much around it, at 1 mm a pixel

// The homography taking the card's millimetres (corner 0 at the origin, 0 -> 1 along +x) to the
// frame's pixels.
Eigen::Matrix3d card_homography(const std::array<V2, 4>& corners, std::pair<double, double> sides) {
  const cv::Point2f card[4] = {
      {0, 0}, {float(sides.first), 0}, {float(sides.first), float(sides.second)}, {0, float(sides.second)}};
  cv::Point2f image[4];
  for (int k = 0; k < 4; ++k) image[k] = cv::Point2f(float(corners[k].x()), float(corners[k].y()));
  const cv::Mat h = cv::getPerspectiveTransform(card, image);  // CV_64F
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = h.at<double>(r, c);
  return m;
}

// The frame around the card resampled onto its millimetres: pixel (i, j) at mm (i - B + 0.5, j - B + 0.5).
cv::Mat card_plane(const cv::Mat& grey, int width, int height, const Eigen::Matrix3d& h,
                   std::pair<double, double> sides) {
  Eigen::Matrix3d to_mm = Eigen::Matrix3d::Identity(), to_grey = Eigen::Matrix3d::Identity();
  to_mm(0, 2) = to_mm(1, 2) = 0.5 - kBorderMm;
  // OpenCV's pixel centres are at integers, the dataset's at i + 0.5.
  to_grey(0, 0) = double(grey.cols) / width, to_grey(1, 1) = double(grey.rows) / height;
  to_grey(0, 2) = to_grey(1, 2) = -0.5;
  const Eigen::Matrix3d m = to_grey * h * to_mm;
  cv::Mat mcv(3, 3, CV_64F);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) mcv.at<double>(r, c) = m(r, c);
  cv::Mat out;
  const cv::Size size(int(std::ceil(sides.first)) + 2 * kBorderMm,
                      int(std::ceil(sides.second)) + 2 * kBorderMm);
  cv::warpPerspective(grey, out, mcv, size, cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REPLICATE);
  out.convertTo(out, CV_32F);
  return out;
}

struct Edge {
  V2 start, dir, inward;  // millimetres; dir and inward unit
  double length;
};

std::array<Edge, 4> card_edges(std::pair<double, double> s) {
  const auto [a, b] = s;
  return {Edge{{0, 0}, {1, 0}, {0, 1}, a}, Edge{{a, 0}, {0, 1}, {-1, 0}, b},
          Edge{{a, b}, {-1, 0}, {0, -1}, a}, Edge{{0, b}, {0, -1}, {1, 0}, b}};
}

struct Place {
  double inside, step;  // mean grey 2-5 mm inside the edge; |inside - the same outside|
};

// The places at each millimetre along the edge, 5 mm clear of its corners.
std::vector<Place> edge_places(const cv::Mat& plane, const Edge& e) {
  auto at = [&](const V2& mm) {
    const int x = std::clamp(int(std::floor(mm.x() + kBorderMm)), 0, plane.cols - 1);
    const int y = std::clamp(int(std::floor(mm.y() + kBorderMm)), 0, plane.rows - 1);
    return double(plane.at<float>(y, x));
  };
  std::vector<Place> places;
  for (double t = 5.0; t <= e.length - 5.0; t += 1.0) {
    const V2 p = e.start + t * e.dir;
    double in = 0, out = 0;
    for (int d = 2; d <= 5; ++d) in += at(p + d * e.inward), out += at(p - d * e.inward);
    places.push_back({in / 4.0, std::abs(in - out) / 4.0});
  }
  return places;
}

double median_of(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// The strip from edge places [t0, t1] (mm along the edge) outward, in the frame's pixels; nothing
// when part of it would lie beyond the card plane's horizon in the image.
std::optional<dataset::IgnorePolygon> strip(const Edge& e, double t0, double t1, const Eigen::Matrix3d& h,
                                            const CardFingerOptions& o) {
  const V2 a = e.start + (t0 - o.side_mm) * e.dir, b = e.start + (t1 + o.side_mm) * e.dir;
  const V2 out = -o.finger_length_mm * e.inward;
  dataset::IgnorePolygon poly;
  for (const V2& p : {a, b, V2(b + out), V2(a + out)}) {
    const Eigen::Vector3d q = h * Eigen::Vector3d(p.x(), p.y(), 1.0);
    if (q.z() <= 1e-9) return std::nullopt;
    poly.emplace_back(float(q.x() / q.z()), float(q.y() / q.z()));
  }
  return poly;
}

}  // namespace

std::vector<dataset::IgnorePolygon> finger_strips(const cv::Mat& grey, int width, int height,
                                                  const std::array<Eigen::Vector2d, 4>& corners,
                                                  std::pair<double, double> sides,
                                                  const CardFingerOptions& options) {
  std::vector<dataset::IgnorePolygon> strips;
  const Eigen::Matrix3d h = card_homography(corners, sides);
  // The homography is fixed up to scale; its sign makes the card's own points lie at w > 0.
  const Eigen::Matrix3d hs = (h * Eigen::Vector3d(sides.first / 2, sides.second / 2, 1)).z() < 0 ? -h : h;
  const cv::Mat plane = card_plane(grey, width, height, hs, sides);
  const auto edges = card_edges(sides);
  std::array<std::vector<Place>, 4> places;
  std::vector<double> steps, insides;
  for (int k = 0; k < 4; ++k) {
    places[k] = edge_places(plane, edges[k]);
    for (const Place& p : places[k]) steps.push_back(p.step), insides.push_back(p.inside);
  }
  if (steps.empty()) return strips;
  const double step = median_of(steps), inside = median_of(insides);
  if (step < options.min_median_step) return strips;
  for (int k = 0; k < 4; ++k) {
    const auto& s = places[k];
    // A finger is on both sides of the edge (no step) and is not the card (its inside differs from the
    // card's usual inside); a pale wall beside a pale card is the first only.
    const auto covered = [&](size_t i) {
      return s[i].step < options.covered_step * step &&
             std::abs(s[i].inside - inside) > options.covered_step * step;
    };
    size_t n_covered = 0;
    for (size_t i = 0; i < s.size(); ++i) n_covered += covered(i);
    if (n_covered > options.max_covered * double(s.size())) continue;
    for (size_t i = 0; i < s.size();) {
      size_t j = i;
      while (j < s.size() && covered(j)) ++j;
      if (double(j - i) >= options.min_stretch_mm)  // places are 1 mm apart, from 5 mm
        if (auto p = strip(edges[k], 5.0 + double(i), 5.0 + double(j - 1), hs, options)) strips.push_back(*p);
      i = j > i ? j : i + 1;
    }
  }
  return strips;
}

}  // namespace lorgnette::capture
