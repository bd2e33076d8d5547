// Per-side temple spread search (see temple_fit.h).
#include "fit/temple_fit.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "fit/place.h"

namespace lorgnette::fit {
namespace {

constexpr int kBatch = 8;  // angles per density query (fewer, larger queries for a NeRF)

Eigen::Vector3d to_scene(const Eigen::Matrix4d& t, const Eigen::Vector3d& p) {
  return t.block<3, 3>(0, 0) * p + t.block<3, 1>(0, 3);
}

std::vector<Eigen::Vector3d> placed(const TempleFitInputs& in, const mesh::TempleBend& bend,
                                    const std::vector<Eigen::Vector3d>& pts) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(pts.size());
  for (const auto& p : pts) out.push_back(to_scene(in.transform, mesh::bend_point(bend, p)));
  return out;
}

// For each angle: true when the side's samples, spread by it, penetrate at most `limit_mm`
// (penetration_depths_mm stopped at the limit; all angles of the batch in one walk).
std::vector<bool> passes(const TempleFitInputs& in, const HeadProbe& head, mesh::TempleBend bend, int side,
                         const std::vector<Eigen::Vector3d>& pts, const std::vector<double>& angles,
                         double limit_mm) {
  const ContactOptions& c = head.contact;
  std::vector<Eigen::Vector3d> q;
  std::vector<size_t> owner;
  for (size_t a = 0; a < angles.size(); ++a) {
    (side > 0 ? bend.left : bend.right).spread_deg = angles[a];
    for (const auto& p : placed(in, bend, pts)) q.push_back(p), owner.push_back(a);
  }
  const int probes = static_cast<int>(std::floor(limit_mm / c.step_mm + 1e-9));
  auto depth = penetration_depths_mm(head, q, probes);
  std::vector<bool> ok(angles.size(), true);
  for (size_t i = 0; i < q.size(); ++i)
    if (depth[i] > probes * c.step_mm + 1e-9) ok[owner[i]] = false;
  return ok;
}

double penetration(const TempleFitInputs& in, const HeadProbe& head, const mesh::TempleBend& bend,
                   const std::vector<Eigen::Vector3d>& pts) {
  return penetration_depth_mm(head, placed(in, bend, pts));
}

// The smallest angle on the search grid that passes; the maximum when none does.
double search_spread(const TempleFitInputs& in, const HeadProbe& head, const mesh::TempleBend& bend, int side,
                     const std::vector<Eigen::Vector3d>& pts, double limit_mm, const TempleFitOptions& opt) {
  std::vector<double> grid;
  const int n = static_cast<int>(std::floor(opt.max_spread_deg / opt.step_deg + 1e-9));
  for (int k = 1; k <= n; ++k) grid.push_back(k * opt.step_deg);
  if (grid.empty() || grid.back() < opt.max_spread_deg - 1e-9) grid.push_back(opt.max_spread_deg);
  for (size_t b = 0; b < grid.size(); b += kBatch) {
    std::vector<double> batch(grid.begin() + b, grid.begin() + std::min(grid.size(), b + kBatch));
    std::vector<bool> ok = passes(in, head, bend, side, pts, batch, limit_mm);
    for (size_t i = 0; i < batch.size(); ++i)
      if (ok[i]) return batch[i];
  }
  return opt.max_spread_deg;
}

}  // namespace

TempleFitResult fit_temples(const TempleFitInputs& in, const HeadProbe& head, double max_penetration_mm,
                            const TempleFitOptions& opt) {
  if (!(opt.step_deg > 0.0) || !(opt.max_spread_deg > 0.0) || opt.max_spread_deg > 60.0 ||
      !(opt.ramp_mm > 0.0))
    throw std::runtime_error(
        fmt::format("temple fit: need 0 < step ({}) and 0 < max spread ({}) <= 60 degrees and a "
                    "ramp > 0 ({} mm)",
                    opt.step_deg, opt.max_spread_deg, opt.ramp_mm));
  if (!(head.mm_per_unit > 0.0)) throw std::runtime_error("temple fit: mm_per_unit must be > 0");
  TempleFitResult res;
  res.fitted = true;
  res.bend.left.hinge = in.hinge_l;
  res.bend.right.hinge = in.hinge_r;
  res.bend.ramp_mm = opt.ramp_mm;
  for (int side : {+1, -1}) {
    TempleSideFit& sf = side > 0 ? res.left : res.right;
    std::vector<Eigen::Vector3d> pts;
    for (const auto& p : head.frame_points)
      if (mesh::temple_side(res.bend, p) == side) pts.push_back(p);
    sf.points = static_cast<int>(pts.size());
    if (pts.empty()) continue;
    sf.penetration_before_mm = sf.penetration_mm = penetration(in, head, res.bend, pts);
    if (sf.penetration_before_mm > max_penetration_mm) {
      double a = search_spread(in, head, res.bend, side, pts, max_penetration_mm, opt);
      (side > 0 ? res.bend.left : res.bend.right).spread_deg = a;
      sf.spread_deg = a;
      sf.penetration_mm = penetration(in, head, res.bend, pts);
    }
    sf.clear = sf.penetration_mm <= max_penetration_mm + 1e-9;
  }
  return res;
}

std::vector<std::string> temple_warnings(const TempleFitResult& r) {
  std::vector<std::string> out;
  if (!r.fitted) return out;
  for (int side : {+1, -1}) {
    const TempleSideFit& t = side > 0 ? r.left : r.right;
    if (t.clear) continue;
    out.push_back(
        fmt::format("the {} temple still passes {:.2f} mm into the head at the largest spread ({:.1f} deg; "
                    "{:.2f} mm rigid): the frame is too narrow for this head",
                    side > 0 ? "left" : "right", t.penetration_mm, t.spread_deg, t.penetration_before_mm));
  }
  return out;
}

}  // namespace lorgnette::fit
