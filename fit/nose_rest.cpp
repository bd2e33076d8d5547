// The front's resting height on the nose (see nose_rest.h).
#include "fit/nose_rest.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lorgnette::fit {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Per set i in `which`: whether sets[i] + k[i] * step all lie outside the head.
std::vector<bool> clear_at(const DensityFn& density, float threshold, const PointSets& sets,
                           const std::vector<size_t>& which, const std::vector<int>& k,
                           const Eigen::Vector3d& step) {
  std::vector<Eigen::Vector3f> q;
  std::vector<size_t> owner;
  for (size_t j = 0; j < which.size(); ++j)
    for (const auto& p : sets[which[j]])
      q.push_back((p + double(k[j]) * step).cast<float>()), owner.push_back(j);
  const std::vector<float> sigma = density(q);
  if (sigma.size() != q.size())
    throw std::runtime_error(
        fmt::format("density query returned {} values for {} points", sigma.size(), q.size()));
  std::vector<bool> clear(which.size(), true);
  for (size_t i = 0; i < q.size(); ++i)
    if (sigma[i] > threshold) clear[owner[i]] = false;
  return clear;
}

// The lowest height at which the front rests on its bridge: it clears within `tolerance` of where
// the bridge alone rests on the nose, there or at Eq. 4's height; else Eq. 4's height when the front
// clears there; else (it cannot clear at Eq. 4's height) the lowest height within `tolerance` of the
// front's least-forward rest.
size_t choose_height(const std::vector<double>& shifts, const std::vector<double>& bridge, double tolerance) {
  for (size_t j = 0; j < shifts.size(); ++j)
    if (shifts[j] <= std::max(bridge[j], bridge.front()) + tolerance) return j;
  if (std::isfinite(shifts.front())) return 0;
  const double least = *std::min_element(shifts.begin(), shifts.end());
  if (!std::isfinite(least)) return 0;
  for (size_t j = 0; j < shifts.size(); ++j)
    if (shifts[j] <= least + tolerance) return j;
  return 0;
}

}  // namespace

std::vector<double> clearing_shifts_mm(const DensityFn& density, float threshold, const PointSets& sets,
                                       const Eigen::Vector3d& mm_fwd, double step_mm, double max_shift_mm) {
  if (!(step_mm > 0.0) || !(max_shift_mm >= step_mm))
    throw std::runtime_error(
        fmt::format("clearing shifts: need 0 < step ({} mm) <= range ({} mm)", step_mm, max_shift_mm));
  std::vector<double> out(sets.size(), -kInf);
  if (sets.empty()) return out;
  const int kmax = int(std::floor(max_shift_mm / step_mm + 1e-9));
  const Eigen::Vector3d step = step_mm * mm_fwd;
  std::vector<size_t> all(sets.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = i;
  const std::vector<bool> far_back =
      clear_at(density, threshold, sets, all, std::vector<int>(all.size(), -kmax), step);
  const std::vector<bool> far_out =
      clear_at(density, threshold, sets, all, std::vector<int>(all.size(), kmax), step);
  std::vector<int> lo(sets.size(), -kmax), hi(sets.size(), kmax);  // lo: inside, hi: clear
  std::vector<size_t> active;
  for (size_t i = 0; i < sets.size(); ++i) {
    if (far_back[i]) continue;  // nothing to rest on: -infinity
    if (!far_out[i]) {
      out[i] = kInf;
      continue;
    }
    active.push_back(i);
  }
  while (!active.empty()) {
    std::vector<int> mid;
    for (size_t i : active) mid.push_back((lo[i] + hi[i]) / 2);
    const std::vector<bool> clear = clear_at(density, threshold, sets, active, mid, step);
    std::vector<size_t> next;
    for (size_t j = 0; j < active.size(); ++j) {
      const size_t i = active[j];
      (clear[j] ? hi[i] : lo[i]) = mid[j];
      if (hi[i] - lo[i] > 1) next.push_back(i);
    }
    active.swap(next);
  }
  for (size_t i = 0; i < sets.size(); ++i)
    if (out[i] == -kInf && !far_back[i]) out[i] = hi[i] * step_mm;
  return out;
}

NoseRest nose_rest(const HeadProbe& head, const std::vector<double>& heights_mm, const PointSets& front,
                   const PointSets& bridge, const Eigen::Vector3d& mm_fwd) {
  const ContactOptions& o = head.contact;
  NoseRest rest;
  if (heights_mm.empty() || front.size() != heights_mm.size() || bridge.size() != heights_mm.size() ||
      bridge.front().empty())
    return rest;
  rest.heights_mm = heights_mm;
  const float thr = o.density_threshold;
  rest.shifts_mm = clearing_shifts_mm(head.density, thr, front, mm_fwd, o.step_mm, o.max_shift_mm);
  rest.bridge_shifts_mm = clearing_shifts_mm(head.density, thr, bridge, mm_fwd, o.step_mm, o.max_shift_mm);
  rest.chosen = choose_height(rest.shifts_mm, rest.bridge_shifts_mm, o.rest_tolerance_mm);
  rest.rise_mm = heights_mm[rest.chosen];
  return rest;
}

}  // namespace lorgnette::fit
