// The card's scale from posed frames; see card_scale.h.
#include "capture/card_scale.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <random>

#include "fit/camera_math.h"

namespace lorgnette::capture {
namespace {

using V2 = Eigen::Vector2d;
using V3 = Eigen::Vector3d;
using Corners3 = std::array<V3, 4>;

// One frame's quad, its corners rotated to the card's order.
struct Observation {
  int view;
  std::array<V2, 4> corners;
};

double image_tolerance(const Camera& c, const CardScaleOptions& o) {
  return 1.5 + o.reprojection_px * std::hypot(double(c.width), double(c.height));
}

// Largest corner distance between `corners` and the card's reprojection; +inf when behind the camera.
double reprojection_error(const Camera& cam, const Corners3& card, const std::array<V2, 4>& corners) {
  double worst = 0;
  for (int k = 0; k < 4; ++k) {
    V2 uv;
    if (!fit::camera_project(cam, card[k], &uv)) return INFINITY;
    worst = std::max(worst, (uv - corners[k]).norm());
  }
  return worst;
}

// The candidate and rotation of its corners that best match the card in view v, if within tolerance.
std::optional<Observation> match(const CardView& view, int v, const Corners3& card, double tolerance) {
  std::optional<Observation> best;
  double best_err = tolerance;
  for (const CardQuad& q : view.candidates)
    for (int r = 0; r < 4; ++r) {
      std::array<V2, 4> c;
      for (int k = 0; k < 4; ++k) c[k] = q.corners[(k + r) % 4];
      const double err = reprojection_error(view.camera, card, c);
      if (err < best_err) best_err = err, best = Observation{v, c};
    }
  return best;
}

Corners3 triangulate(const std::vector<CardView>& views, const std::vector<Observation>& obs) {
  Corners3 card;
  for (int k = 0; k < 4; ++k) {
    std::vector<V3> origins, dirs;
    for (const auto& o : obs) {
      fit::Ray ray = fit::camera_ray(views[size_t(o.view)].camera, o.corners[k]);
      origins.push_back(ray.origin), dirs.push_back(ray.dir);
    }
    card[k] = nearest_point_to_rays(origins, dirs);
  }
  return card;
}

std::array<double, 4> edge_lengths(const Corners3& c) {
  return {(c[1] - c[0]).norm(), (c[2] - c[1]).norm(), (c[3] - c[2]).norm(), (c[0] - c[3]).norm()};
}

double scale_of(const Corners3& c) {
  const auto e = edge_lengths(c);
  return 2.0 * (kCardWidthMm + kCardHeightMm) / (e[0] + e[1] + e[2] + e[3]);
}

// Where the cameras aim (nearest point to their optical axes) and their median distance from it.
std::pair<V3, double> camera_focus(const std::vector<CardView>& views) {
  std::vector<V3> origins, dirs;
  for (const auto& v : views)
    origins.push_back(fit::camera_center(v.camera)), dirs.push_back(fit::camera_forward(v.camera));
  const V3 focus = views.size() >= 2 ? nearest_point_to_rays(origins, dirs) : origins[0] + dirs[0];
  std::vector<double> d;
  for (const auto& o : origins) d.push_back((o - focus).norm());
  std::nth_element(d.begin(), d.begin() + long(d.size() / 2), d.end());
  return {focus, d[d.size() / 2]};
}

// A card hypothesis from two frames' quads is worth testing when it has a card's shape and lies at the
// face the cameras aim at.
bool card_like(const Corners3& c, const V3& focus, double reach) {
  const V3 centre = 0.25 * (c[0] + c[1] + c[2] + c[3]);
  if ((centre - focus).norm() > reach) return false;
  const auto e = edge_lengths(c);
  const double a = e[0] + e[2], b = e[1] + e[3], aspect = std::max(a, b) / std::min(a, b);
  return std::abs(aspect / (kCardWidthMm / kCardHeightMm) - 1.0) < 0.15;
}

// The card the most frames agree on: hypotheses from pairs of frames far enough apart, each kept by
// the frames whose quads it reprojects onto. Deterministic (fixed seed for the pairs tried).
std::vector<Observation> consensus(const std::vector<CardView>& views, const CardScaleOptions& o) {
  std::vector<int> with;
  for (int i = 0; i < int(views.size()); ++i)
    if (!views[size_t(i)].candidates.empty()) with.push_back(i);
  std::vector<std::pair<int, int>> pairs;
  for (size_t a = 0; a < with.size(); ++a)
    for (size_t b = a + 1; b < with.size(); ++b) pairs.push_back({with[a], with[b]});
  std::mt19937 rng(7);
  std::shuffle(pairs.begin(), pairs.end(), rng);
  if (pairs.size() > 300) pairs.resize(300);
  auto [focus, distance] = camera_focus(views);
  std::vector<Observation> best;
  for (auto [i, j] : pairs)
    for (const CardQuad& qa : views[size_t(i)].candidates)
      for (const CardQuad& qb : views[size_t(j)].candidates)
        for (int r = 0; r < 4; ++r) {
          Observation oa{i, qa.corners}, ob{j, {}};
          for (int k = 0; k < 4; ++k) ob.corners[k] = qb.corners[(k + r) % 4];
          const Corners3 card = triangulate(views, {oa, ob});
          if (!card_like(card, focus, o.focus_reach * distance)) continue;
          std::vector<Observation> agree;
          for (int v : with)
            if (auto m = match(views[size_t(v)], v, card, image_tolerance(views[size_t(v)].camera, o)))
              agree.push_back(*m);
          if (agree.size() > best.size()) best = std::move(agree);
        }
  return best;
}

// Leaves out the frames whose corners lie off the triangulated card by more than 3 times the median
// error (at least 1.5 px), and those seeing its face more obliquely than allowed; counts the latter.
std::vector<Observation> keep_consistent(const std::vector<CardView>& views, std::vector<Observation> obs,
                                         const CardScaleOptions& o, int& oblique) {
  const Corners3 card = triangulate(views, obs);
  std::vector<double> err;
  for (const auto& ob : obs)
    err.push_back(reprojection_error(views[size_t(ob.view)].camera, card, ob.corners));
  std::vector<double> sorted = err;
  std::nth_element(sorted.begin(), sorted.begin() + long(sorted.size() / 2), sorted.end());
  const double limit = std::max(1.5, 3.0 * sorted[sorted.size() / 2]);
  const V3 centre = 0.25 * (card[0] + card[1] + card[2] + card[3]);
  const V3 normal = (card[1] - card[0]).cross(card[3] - card[0]).normalized();
  std::vector<Observation> kept;
  oblique = 0;
  for (size_t i = 0; i < obs.size(); ++i) {
    const V3 to_cam = (fit::camera_center(views[size_t(obs[i].view)].camera) - centre).normalized();
    const double angle = std::acos(std::min(1.0, std::abs(to_cam.dot(normal)))) * 180.0 / M_PI;
    if (angle > o.max_obliquity_deg) {
      ++oblique;
      continue;
    }
    if (err[i] <= limit) kept.push_back(obs[i]);
  }
  return kept;
}

// "" when the card's edges agree with a flat ID-1 card, else what disagrees.
std::string shape_problem(const Corners3& c, const CardScaleOptions& o) {
  const auto e = edge_lengths(c);
  const double s = scale_of(c);
  const bool first_long = e[0] + e[2] > e[1] + e[3];
  const double l0 = s * e[first_long ? 0 : 1], l1 = s * e[first_long ? 2 : 3];
  const double s0 = s * e[first_long ? 1 : 0], s1 = s * e[first_long ? 3 : 2];
  const double d0 = (c[2] - c[0]).norm(), d1 = (c[3] - c[1]).norm();
  const double aspect = (l0 + l1) / (s0 + s1);
  if (std::abs(l0 - l1) > o.max_edge_mismatch * 0.5 * (l0 + l1) ||
      std::abs(s0 - s1) > o.max_edge_mismatch * 0.5 * (s0 + s1) ||
      std::abs(aspect / (kCardWidthMm / kCardHeightMm) - 1.0) > o.max_aspect_error ||
      std::abs(d0 - d1) > o.max_diagonal_error * 0.5 * (d0 + d1))
    return fmt::format(
        "its edges disagree (long {:.1f} and {:.1f} mm, short {:.1f} and {:.1f} mm, diagonals {:.1f} and "
        "{:.1f} mm at the scale they average to; a flat ID-1 card is 85.60 x 53.98 mm): the card is bent, "
        "not held flat and still, or not an ID-1 card",
        l0, l1, s0, s1, s * d0, s * d1);
  return "";
}

}  // namespace

V3 nearest_point_to_rays(const std::vector<V3>& origins, const std::vector<V3>& dirs) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  V3 b = V3::Zero();
  for (size_t i = 0; i < origins.size(); ++i) {
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - dirs[i] * dirs[i].transpose();
    A += P, b += P * origins[i];
  }
  return A.ldlt().solve(b);
}

CardScale measure_card_scale(const std::vector<CardView>& views, const CardScaleOptions& o) {
  CardScale r;
  const std::string advice =
      "to measure true size, hold an ID-1 card (a bank, loyalty or library card, 85.60 x 53.98 mm) flat "
      "against the forehead, printed side to the camera, for at least a few seconds of the sweep";
  const size_t seen = size_t(
      std::count_if(views.begin(), views.end(), [](const CardView& v) { return !v.candidates.empty(); }));
  if (seen < 2) {
    r.message =
        fmt::format("no card found ({} of {} frames show a card-like quad): {}", seen, views.size(), advice);
    return r;
  }
  std::vector<Observation> obs = consensus(views, o);
  int oblique = 0;
  if (int(obs.size()) >= 2) obs = keep_consistent(views, obs, o, oblique);
  if (int(obs.size()) < o.min_frames) {
    r.message = oblique > 0 ? fmt::format(
                                  "the card was seen too obliquely in {} frames (more than {:.0f} deg "
                                  "off its face) and clearly in only {}; at least {} are needed: {}",
                                  oblique, o.max_obliquity_deg, obs.size(), o.min_frames, advice)
                            : fmt::format(
                                  "a card was found in only {} frames that agree (at least {} are "
                                  "needed): {}",
                                  obs.size(), o.min_frames, advice);
    return r;
  }
  const Corners3 card = triangulate(views, obs);
  if (std::string problem = shape_problem(card, o); !problem.empty()) {
    r.message = fmt::format("the card in {} frames gives no scale: {}; {}", obs.size(), problem, advice);
    return r;
  }
  r.mm_per_unit = scale_of(card);
  // Jackknife over the frames: the spread of the scale with each frame left out.
  const size_t n = obs.size();
  std::vector<double> partial;
  for (size_t i = 0; i < n; ++i) {
    std::vector<Observation> rest = obs;
    rest.erase(rest.begin() + long(i));
    partial.push_back(scale_of(triangulate(views, rest)));
  }
  const double mean = std::accumulate(partial.begin(), partial.end(), 0.0) / double(n);
  double ss = 0;
  for (double p : partial) ss += (p - mean) * (p - mean);
  r.uncertainty = std::sqrt(double(n - 1) / double(n) * ss);
  r.found = true;
  r.frames = int(n);
  r.corners = card;
  const auto e = edge_lengths(card);
  for (int k = 0; k < 4; ++k) r.edges_mm[k] = e[k] * r.mm_per_unit;
  for (const auto& ob : obs) {
    r.frame_names.push_back(views[size_t(ob.view)].name);
    r.frame_corners.push_back(ob.corners);
  }
  r.message = fmt::format(
      "card in {} frames: {:.3f} +- {:.3f} mm per unit (edges {:.2f}, {:.2f}, {:.2f}, {:.2f} mm)", n,
      r.mm_per_unit, r.uncertainty, r.edges_mm[0], r.edges_mm[1], r.edges_mm[2], r.edges_mm[3]);
  return r;
}

}  // namespace lorgnette::capture
