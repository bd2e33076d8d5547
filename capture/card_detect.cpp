// Card detection in one photo; see card_detect.h.
#include "capture/card_detect.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>

namespace lorgnette::capture {
namespace {

using V2 = Eigen::Vector2d;

struct Line {
  V2 p, d;  // a point and the unit direction
};

struct Outline {
  std::vector<cv::Point> contour;
  int polarity;  // +1: brighter than the surroundings, -1: darker
};

std::optional<V2> intersect(const Line& a, const Line& b) {
  const double den = a.d.x() * b.d.y() - a.d.y() * b.d.x();
  if (std::abs(den) < 1e-6) return std::nullopt;
  const V2 w = b.p - a.p;
  return a.p + a.d * ((w.x() * b.d.y() - w.y() * b.d.x()) / den);
}

void add_outlines(const cv::Mat& bin, int polarity, double min_area, double max_area,
                  std::vector<Outline>& out) {
  static const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, {3, 3});
  cv::Mat open;
  cv::morphologyEx(bin, open, cv::MORPH_OPEN, kernel);  // cuts one-pixel bridges to the background
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(open, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  for (auto& c : contours) {
    const double a = cv::contourArea(c);
    if (a >= min_area && a <= max_area) out.push_back({std::move(c), polarity});
  }
}

// Outer contours of regions brighter or darker than their neighbourhood (local thresholds) and of
// regions above or below each of a ladder of grey levels (a card as bright as the wall behind its
// neighbourhood is still the brightest at some level), sized like a card could be.
std::vector<Outline> candidate_outlines(const cv::Mat& grey, const CardDetectOptions& o) {
  const double area = double(grey.cols) * grey.rows, lo = o.min_area_fraction * area,
               hi = o.max_area_fraction * area;
  const int block = std::max(15, (std::min(grey.cols, grey.rows) / 4) | 1);
  std::vector<Outline> out;
  for (int polarity : {1, -1}) {
    cv::Mat bin;
    cv::adaptiveThreshold(grey, bin, 255, cv::ADAPTIVE_THRESH_MEAN_C,
                          polarity > 0 ? cv::THRESH_BINARY : cv::THRESH_BINARY_INV, block, -8.0 * polarity);
    add_outlines(bin, polarity, lo, hi, out);
    for (int level = 30; level <= 240; level += 15) {
      cv::threshold(grey, bin, level, 255, polarity > 0 ? cv::THRESH_BINARY : cv::THRESH_BINARY_INV);
      add_outlines(bin, polarity, lo, hi, out);
    }
  }
  return out;
}

// The side lines of a card-shaped hull: of every four of the simplified hull's sides (in order around
// it) whose lines make a convex quadrilateral holding the whole hull, the four longest together. A
// finger over a corner cuts it off the hull; the cut is then the side left out, and the corner is
// where the lines of its two neighbours meet.
std::optional<std::array<Line, 4>> choose_sides(const std::vector<cv::Point>& poly) {
  const int n = int(poly.size());
  std::vector<Line> lines(static_cast<size_t>(n));
  std::vector<double> len(static_cast<size_t>(n), 0.0);
  std::vector<V2> pts;
  for (const auto& p : poly) pts.emplace_back(p.x + 0.5, p.y + 0.5);
  for (int i = 0; i < n; ++i) {
    const V2 d = pts[size_t((i + 1) % n)] - pts[size_t(i)];
    len[size_t(i)] = d.norm(), lines[size_t(i)] = {pts[size_t(i)], d.normalized()};
  }
  const double orient =
      (pts[1] - pts[0]).x() * (pts[2] - pts[1]).y() - (pts[1] - pts[0]).y() * (pts[2] - pts[1]).x();
  std::optional<std::array<Line, 4>> best;
  double best_len = 0;
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      for (int c = b + 1; c < n; ++c)
        for (int d = c + 1; d < n; ++d) {
          const std::array<Line, 4> q = {lines[size_t(a)], lines[size_t(b)], lines[size_t(c)],
                                         lines[size_t(d)]};
          const double total = len[size_t(a)] + len[size_t(b)] + len[size_t(c)] + len[size_t(d)];
          if (total <= best_len) continue;
          bool holds = true;
          for (const Line& l : q)
            for (const V2& p : pts) {
              const V2 w = p - l.p;
              const double side = l.d.x() * w.y() - l.d.y() * w.x();  // > 0 inside for orient > 0
              if ((orient > 0 ? side : -side) < -1.5) holds = false;
            }
          if (holds) best = q, best_len = total;
        }
  return best;
}

// The card's side lines from its outline's convex hull; nullopt when the hull is not roughly a
// quadrilateral or the region fills too little of it.
std::optional<std::array<Line, 4>> hull_sides(const std::vector<cv::Point>& contour) {
  std::vector<cv::Point> hull, poly;
  cv::convexHull(contour, hull);
  const double hull_area = cv::contourArea(hull), perimeter = cv::arcLength(hull, true);
  if (hull_area <= 0 || cv::contourArea(contour) < 0.55 * hull_area) return std::nullopt;
  cv::approxPolyDP(hull, poly, 0.01 * perimeter, true);
  if (poly.size() < 4 || poly.size() > 12) return std::nullopt;
  return choose_sides(poly);
}

double bilinear(const cv::Mat& f, const V2& p) {
  const double x = std::clamp(p.x() - 0.5, 0.0, f.cols - 1.001),
               y = std::clamp(p.y() - 0.5, 0.0, f.rows - 1.001);
  const int i = int(x), j = int(y);
  const double fx = x - i, fy = y - j;
  auto at = [&](int r, int c) { return double(f.at<float>(r, c)); };
  return (1 - fy) * ((1 - fx) * at(j, i) + fx * at(j, i + 1)) +
         fy * ((1 - fx) * at(j + 1, i) + fx * at(j + 1, i + 1));
}

struct EdgeFit {
  Line line;
  double support = 0.0, contrast = 0.0;
};

// Re-measures the side from `a` to `b` (the card lies on the side of `inside`): the strongest step of
// the card's polarity along the normal at places spread over the side, a line through them, and the
// places off that line by more than 0.8 px (a finger, a shadow) left out.
std::optional<EdgeFit> refine_side(const cv::Mat& grey, const V2& a, const V2& b, const V2& inside,
                                   int polarity) {
  const double len = (b - a).norm();
  if (len < 8.0) return std::nullopt;
  const V2 t = (b - a) / len;
  V2 n(-t.y(), t.x());
  if (n.dot(inside - a) > 0) n = -n;  // outwards
  const int places = std::clamp(int(len / 2.0), 12, 80);
  const double reach = std::max(3.0, 0.06 * len);
  std::vector<V2> pts;
  std::vector<double> steps;
  for (int k = 0; k < places; ++k) {
    const V2 p = a + (b - a) * (0.1 + 0.8 * (k + 0.5) / places);
    double best = 0, best_s = 0, prev = 0, next = 0;
    for (double s = -reach; s <= reach; s += 0.5) {
      const double step = polarity * (bilinear(grey, p + (s - 0.5) * n) - bilinear(grey, p + (s + 0.5) * n));
      if (step > best) best = step, best_s = s;
    }
    if (best < 6.0) continue;
    prev = polarity * (bilinear(grey, p + (best_s - 1.0) * n) - bilinear(grey, p + best_s * n));
    next = polarity * (bilinear(grey, p + best_s * n) - bilinear(grey, p + (best_s + 1.0) * n));
    const double den = prev - 2 * best + next, off = std::abs(den) > 1e-9 ? 0.25 * (prev - next) / den : 0.0;
    pts.push_back(p + (best_s + std::clamp(off, -0.5, 0.5)) * n);
    steps.push_back(best);
  }
  Line line{a, t};
  std::vector<int> keep;
  for (double tol : {2.0, 0.8, 0.8}) {
    keep.clear();
    for (int i = 0; i < int(pts.size()); ++i) {
      const V2 w = pts[i] - line.p;
      if (std::abs(w.x() * line.d.y() - w.y() * line.d.x()) < tol) keep.push_back(i);
    }
    if (keep.size() < 4) return std::nullopt;
    V2 mean = V2::Zero();
    for (int i : keep) mean += pts[i];
    mean /= double(keep.size());
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (int i : keep) cov += (pts[i] - mean) * (pts[i] - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
    line = {mean, es.eigenvectors().col(1)};
  }
  EdgeFit fit{line, double(keep.size()) / places, 0.0};
  for (int i : keep) fit.contrast += steps[i] / double(keep.size());
  return fit;
}

// Corners clockwise in the image (y down) from the one nearest the top-left.
std::array<V2, 4> ordered(std::array<V2, 4> c) {
  const V2 m = 0.25 * (c[0] + c[1] + c[2] + c[3]);
  std::sort(c.begin(), c.end(), [&](const V2& a, const V2& b) {
    return std::atan2(a.y() - m.y(), a.x() - m.x()) < std::atan2(b.y() - m.y(), b.x() - m.x());
  });
  int first = 0;
  for (int k = 1; k < 4; ++k)
    if (c[k].sum() < c[first].sum()) first = k;
  std::rotate(c.begin(), c.begin() + first, c.end());
  return c;
}

// Convex, inside the image's neighbourhood, and the card's proportions as perspective may show them.
bool plausible(const std::array<V2, 4>& c, const cv::Size& size, const CardDetectOptions& o) {
  double s[4];
  for (int k = 0; k < 4; ++k) {
    const V2 e0 = c[(k + 1) % 4] - c[k], e1 = c[(k + 2) % 4] - c[(k + 1) % 4];
    if (e0.x() * e1.y() - e0.y() * e1.x() <= 0) return false;
    s[k] = e0.norm();
    if (c[k].x() < -0.1 * size.width || c[k].x() > 1.1 * size.width || c[k].y() < -0.1 * size.height ||
        c[k].y() > 1.1 * size.height)
      return false;
  }
  const double a = s[0] + s[2], b = s[1] + s[3], aspect = std::max(a, b) / std::min(a, b);
  return aspect >= o.min_aspect && aspect <= o.max_aspect;
}

std::optional<CardQuad> measure_quad(const cv::Mat& grey, const Outline& outline,
                                     const CardDetectOptions& o) {
  auto sides = hull_sides(outline.contour);
  if (!sides) return std::nullopt;
  std::array<V2, 4> rough;
  for (int k = 0; k < 4; ++k) {
    auto c = intersect((*sides)[k], (*sides)[(k + 1) % 4]);
    if (!c) return std::nullopt;
    rough[(k + 1) % 4] = *c;
  }
  const V2 centre = 0.25 * (rough[0] + rough[1] + rough[2] + rough[3]);
  CardQuad q;
  std::array<Line, 4> lines;
  for (int k = 0; k < 4; ++k) {
    auto fit = refine_side(grey, rough[k], rough[(k + 1) % 4], centre, outline.polarity);
    if (!fit || fit->support < o.min_edge_support) return std::nullopt;
    lines[k] = fit->line;
    q.edge_support += 0.25 * fit->support;
    q.contrast += 0.25 * fit->contrast;
  }
  for (int k = 0; k < 4; ++k) {
    auto c = intersect(lines[(k + 3) % 4], lines[k]);
    if (!c) return std::nullopt;
    q.corners[k] = *c;
  }
  q.corners = ordered(q.corners);
  if (!plausible(q.corners, grey.size(), o)) return std::nullopt;
  return q;
}

}  // namespace

std::vector<CardQuad> detect_card_quads(const cv::Mat& image, const CardDetectOptions& o) {
  cv::Mat grey, smooth;
  if (image.channels() == 3)
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  else
    grey = image;
  cv::GaussianBlur(grey, grey, {3, 3}, 0.0);
  grey.convertTo(smooth, CV_32F);
  std::vector<CardQuad> found;
  for (const Outline& outline : candidate_outlines(grey, o)) {
    auto q = measure_quad(smooth, outline, o);
    if (!q) continue;
    bool duplicate = false;
    for (auto& f : found)
      if ((f.corners[0] - q->corners[0]).norm() + (f.corners[2] - q->corners[2]).norm() < 6.0) {
        if (q->score() > f.score()) f = *q;
        duplicate = true;
      }
    if (!duplicate) found.push_back(*q);
  }
  std::sort(found.begin(), found.end(),
            [](const CardQuad& a, const CardQuad& b) { return a.score() > b.score(); });
  if (int(found.size()) > o.max_candidates) found.resize(size_t(o.max_candidates));
  return found;
}

}  // namespace lorgnette::capture
