// Scale, Kabsch, translation and contact refinement (see place.h).
#include "fit/place.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "fit/nose_rest.h"

namespace lorgnette::fit {

Eigen::Matrix3d kabsch(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                       const std::vector<double>& weights) {
  if (a.size() != b.size() || a.size() < 2 || (!weights.empty() && weights.size() != a.size()))
    throw std::runtime_error(
        fmt::format("kabsch: need >= 2 matching vector pairs (got {} and {})", a.size(), b.size()));
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < a.size(); ++i) h += (weights.empty() ? 1.0 : weights[i]) * a[i] * b[i].transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d s = svd.singularValues();
  if (s(1) <= 1e-9 * std::max(s(0), 1e-300))
    throw std::runtime_error("kabsch: the vectors are parallel (or zero): the rotation is undetermined");
  Eigen::Matrix3d u = svd.matrixU(), v = svd.matrixV();
  // Reflection check (Eq. 5 via Kabsch 1976): flip the least significant axis if det would be -1.
  double d = (v * u.transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  return v * Eigen::Vector3d(1.0, 1.0, d).asDiagonal() * u.transpose();
}

const char* scale_policy_name(ScalePolicy p) {
  return p == ScalePolicy::kStretch ? "stretch" : p == ScalePolicy::kTrueSize ? "true-size" : "auto";
}

ScalePolicy parse_scale_policy(const std::string& s) {
  if (s == "stretch") return ScalePolicy::kStretch;
  if (s == "true-size") return ScalePolicy::kTrueSize;
  if (s == "auto") return ScalePolicy::kAuto;
  throw std::runtime_error(fmt::format("unknown scale policy '{}': use 'auto', 'stretch' or 'true-size'", s));
}

Placement place_glasses(const GlassesRefPoints& g, const PlaceInputs& in, ScalePolicy policy) {
  Placement p;
  double g_width = (g.g_l - g.g_r).norm();
  if (g_width < 1e-9) throw std::runtime_error("glasses reference points g_l and g_r coincide");
  if (policy == ScalePolicy::kAuto)
    throw std::runtime_error(
        "place_glasses: the scale policy 'auto' must be resolved first (resolve_scale_policy)");
  if (policy == ScalePolicy::kStretch) {
    p.scale = (in.t_l - in.t_r).norm() / g_width;
  } else {
    if (!(in.mm_per_unit > 0.0)) throw std::runtime_error("true-size scaling needs mm_per_unit > 0");
    p.scale = 1.0 / in.mm_per_unit;
  }
  if (!(p.scale > 0.0) || !std::isfinite(p.scale))
    throw std::runtime_error(fmt::format("degenerate scale {} (temples coincide?)", p.scale));
  p.rotation = kabsch({g.g_r - g.g_c, g.g_l - g.g_c}, {in.f_r - in.f_c, in.f_l - in.f_c});  // Eq. 5
  Eigen::Vector3d t = in.f_c - p.scale * p.rotation * g.g_c;  // Eq. 4 (g_c after scale and rotation)
  p.transform.setIdentity();
  p.transform.block<3, 3>(0, 0) = p.scale * p.rotation;
  p.transform.block<3, 1>(0, 3) = t;
  return p;
}

namespace {

std::vector<bool> inside(const DensityFn& density, const std::vector<Eigen::Vector3d>& pts, float thr) {
  std::vector<Eigen::Vector3f> q;
  q.reserve(pts.size());
  for (const auto& p : pts) q.push_back(p.cast<float>());
  std::vector<float> sigma = density(q);
  if (sigma.size() != pts.size())
    throw std::runtime_error(
        fmt::format("density query returned {} values for {} points", sigma.size(), pts.size()));
  std::vector<bool> out(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) out[i] = sigma[i] > thr;
  return out;
}

int count_inside(const DensityFn& density, const std::vector<Eigen::Vector3d>& pts,
                 const Eigen::Vector3d& shift, float thr) {
  std::vector<Eigen::Vector3d> moved;
  for (const auto& p : pts) moved.push_back(p + shift);
  auto in = inside(density, moved, thr);
  return int(std::count(in.begin(), in.end(), true));
}

std::vector<Eigen::Vector3d> transform_points(const Eigen::Matrix4d& t,
                                              const std::vector<Eigen::Vector3d>& pts) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(pts.size());
  for (const auto& p : pts) out.push_back(t.block<3, 3>(0, 0) * p + t.block<3, 1>(0, 3));
  return out;
}

// Debug log: which front points of the frame (canonical mm) still meet the head one step before the
// contact search lets go, so a large shift can be traced to the rims, the bridge or the pads.
void log_blocking_points(const DensityFn& density, const std::vector<Eigen::Vector3d>& front,
                         const std::vector<Eigen::Vector3d>& canon, const Eigen::Vector3d& offset,
                         float thr) {
  if (!spdlog::should_log(spdlog::level::debug)) return;
  std::vector<Eigen::Vector3d> moved;
  for (const auto& p : front) moved.push_back(p + offset);
  const auto in = inside(density, moved, thr);
  for (size_t i = 0; i < in.size(); ++i)
    if (in[i])
      spdlog::debug("fit: contact held by frame point ({:.1f}, {:.1f}, {:.1f}) mm", canon[i].x(),
                    canon[i].y(), canon[i].z());
}

}  // namespace

std::vector<double> penetration_depths_mm(const HeadProbe& head,
                                          const std::vector<Eigen::Vector3d>& scene_points, int max_probes) {
  const ContactOptions& opt = head.contact;
  std::vector<double> depth(scene_points.size(), 0.0);
  auto in = inside(head.density, scene_points, opt.density_threshold);
  std::vector<Eigen::Vector3d> pts, dirs;
  std::vector<size_t> who;
  for (size_t i = 0; i < scene_points.size(); ++i) {
    if (!in[i]) continue;
    Eigen::Vector3d r = scene_points[i] - head.axis_point;
    r -= r.dot(head.d_up) * head.d_up;  // horizontal, away from the head's vertical axis
    pts.push_back(scene_points[i]);
    dirs.push_back(r.norm() > 1e-12 ? r.normalized() : Eigen::Vector3d(head.d_up.unitOrthogonal()));
    who.push_back(i);
    depth[i] = (max_probes + 1) * opt.step_mm;  // until a probe finds it outside
  }
  const double step = opt.step_mm / head.mm_per_unit;
  for (int k = 1; k <= max_probes && !pts.empty(); ++k) {
    std::vector<Eigen::Vector3d> probe;
    for (size_t i = 0; i < pts.size(); ++i) probe.push_back(pts[i] + dirs[i] * (k * step));
    auto still = inside(head.density, probe, opt.density_threshold);
    size_t n = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
      if (still[i])
        pts[n] = pts[i], dirs[n] = dirs[i], who[n] = who[i], ++n;
      else
        depth[who[i]] = k * opt.step_mm;
    }
    pts.resize(n), dirs.resize(n), who.resize(n);
  }
  return depth;
}

double penetration_depth_mm(const HeadProbe& head, const std::vector<Eigen::Vector3d>& scene_points,
                            int* inside_count) {
  const ContactOptions& opt = head.contact;
  const int probes = static_cast<int>(std::floor(2.0 * opt.max_shift_mm / opt.step_mm + 1e-9));
  auto depth = penetration_depths_mm(head, scene_points, probes);
  if (inside_count)
    *inside_count = int(std::count_if(depth.begin(), depth.end(), [](double d) { return d > 0.0; }));
  double deepest = depth.empty() ? 0.0 : *std::max_element(depth.begin(), depth.end());
  return std::min(deepest, probes * opt.step_mm);  // still inside at the last probe: that far at least
}

namespace {

// The slide along d_fwd (`unit`: one mm, scene units): outwards until the front clears, or inwards
// until it first touches; 0 when it touches nothing within range (Eq. 4's depth stays).
double slide_mm(const DensityFn& density, const std::vector<Eigen::Vector3d>& front,
                const Eigen::Vector3d& unit, float thr, const ContactOptions& opt) {
  if (count_inside(density, front, Eigen::Vector3d::Zero(), thr) > 0) {
    double shift = opt.step_mm;
    for (; shift <= opt.max_shift_mm; shift += opt.step_mm)
      if (count_inside(density, front, shift * unit, thr) == 0) break;
    return std::min(shift, opt.max_shift_mm);
  }
  double s = -opt.step_mm;
  for (; s >= -opt.max_shift_mm; s -= opt.step_mm)
    if (count_inside(density, front, s * unit, thr) > 0) break;
  return s < -opt.max_shift_mm ? 0.0 : s + opt.step_mm;  // the last position without contact
}

// The frame raised along `up` to where its front rests on its bridge (nose_rest.h), as a scene
// transform; identity when it rests at Eq. 4's height. `fwd`, `up`: the head's axes, square to each other.
Eigen::Matrix4d rest_on_nose(const HeadProbe& head, const Eigen::Matrix4d& transform,
                             const std::vector<Eigen::Vector3d>& front_canon, const Eigen::Vector3d& fwd,
                             const Eigen::Vector3d& up, double* rise) {
  const ContactOptions& o = head.contact;
  std::vector<Eigen::Vector3d> front_c, bridge_c;
  for (const auto& p : front_canon) (p.norm() <= o.bridge_radius_mm ? bridge_c : front_c).push_back(p);
  front_c.insert(front_c.end(), bridge_c.begin(), bridge_c.end());
  *rise = 0.0;
  if (!(o.max_rise_mm > 0.0) || !(o.rise_step_mm > 0.0) || bridge_c.empty())
    return Eigen::Matrix4d::Identity();
  std::vector<double> heights;
  std::vector<Eigen::Matrix4d> raise;
  PointSets front, bridge;
  for (int j = 0; j <= int(std::floor(o.max_rise_mm / o.rise_step_mm + 1e-9)); ++j) {
    heights.push_back(j * o.rise_step_mm);
    raise.push_back(Eigen::Matrix4d::Identity());
    raise.back().block<3, 1>(0, 3) = heights.back() / head.mm_per_unit * up;
    front.push_back(transform_points(raise.back() * transform, front_c));
    bridge.push_back(transform_points(raise.back() * transform, bridge_c));
  }
  const NoseRest rest = nose_rest(head, heights, front, bridge, fwd / head.mm_per_unit);
  for (size_t j = 0; j < rest.heights_mm.size(); ++j)
    spdlog::debug("fit: nose rest {:+.1f} mm up: front clears at {:+.2f} mm, bridge at {:+.2f} mm",
                  rest.heights_mm[j], rest.shifts_mm[j], rest.bridge_shifts_mm[j]);
  // A shift beyond the search (nose_rest.h: +-infinity) is said as such, not as "inf mm".
  auto gap = [&](double mm) {
    return std::isfinite(mm) ? fmt::format("{:.2f} mm", mm)
                             : fmt::format("more than {:.0f} mm", o.max_shift_mm);
  };
  if (rest.rise_mm > 0.0)
    spdlog::info(
        "fit: the frame rides {:.1f} mm up the nose: at Eq. 4's height its rims meet the nose's sides and "
        "hold its front {} in front of where its bridge rests on the nose; {} there",
        rest.rise_mm, gap(rest.shifts_mm.front() - rest.bridge_shifts_mm.front()),
        gap(rest.shifts_mm[rest.chosen] - rest.bridge_shifts_mm.front()));
  *rise = rest.rise_mm;
  return raise[rest.chosen];
}

}  // namespace

ContactResult refine_contact(Placement& placement, const HeadProbe& head, const Eigen::Vector3d& d_fwd) {
  ContactResult res;
  const ContactOptions& opt = head.contact;
  if (head.frame_points.empty() || !(head.mm_per_unit > 0.0)) return res;
  std::vector<Eigen::Vector3d> front_canon, body_canon;
  for (const auto& p : head.frame_points) {
    if (p.z() > opt.front_z_mm) front_canon.push_back(p);
    if (p.z() >= opt.tip_z_mm) body_canon.push_back(p);
  }
  res.penetration_before_mm = penetration_depth_mm(head, transform_points(placement.transform, body_canon));
  // The head's up, square to d_fwd: the ride changes the height alone.
  const Eigen::Vector3d fwd = d_fwd.normalized();
  const Eigen::Vector3d up = (head.d_up - head.d_up.dot(fwd) * fwd).normalized();
  if (up.allFinite()) {
    const Eigen::Matrix4d raise = rest_on_nose(head, placement.transform, front_canon, fwd, up, &res.rise_mm);
    placement.transform = raise * placement.transform;
  }
  const auto front = transform_points(placement.transform, front_canon);
  const Eigen::Vector3d unit = fwd / head.mm_per_unit;  // one mm along d_fwd, scene units
  const float thr = opt.density_threshold;
  const double shift = slide_mm(head.density, front, unit, thr, opt);
  if (shift > 0.0) log_blocking_points(head.density, front, front_canon, (shift - opt.step_mm) * unit, thr);
  placement.transform.block<3, 1>(0, 3) += shift * unit;
  res.shift_mm = shift;
  res.refined = true;
  measure_contact(res, placement, head);
  return res;
}

void measure_contact(ContactResult& res, const Placement& placement, const HeadProbe& head,
                     const std::vector<Eigen::Vector3d>& deformed) {
  const std::vector<Eigen::Vector3d>& frame_points = head.frame_points;
  if (!deformed.empty() && deformed.size() != frame_points.size())
    throw std::runtime_error("measure_contact: deformed points must match the frame points one to one");
  std::vector<Eigen::Vector3d> front, body, tip;
  for (size_t i = 0; i < frame_points.size(); ++i) {
    const Eigen::Vector3d& p = frame_points[i];
    const Eigen::Vector3d& q = deformed.empty() ? p : deformed[i];
    if (p.z() > head.contact.front_z_mm) front.push_back(q);
    (p.z() >= head.contact.tip_z_mm ? body : tip).push_back(q);
  }
  const Eigen::Matrix4d& t = placement.transform;
  res.penetration_mm = penetration_depth_mm(head, transform_points(t, body), &res.points_inside);
  res.front_penetration_mm = penetration_depth_mm(head, transform_points(t, front));
  res.tip_penetration_mm = penetration_depth_mm(head, transform_points(t, tip));
}

}  // namespace lorgnette::fit
