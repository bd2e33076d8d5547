// The placement pipeline (see fit.h).
#include "fit/fit.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include "fit/debug_draw.h"
#include "fit/front_search.h"
#include "fit/landmark_ids.h"
#include "fit/mean_face.h"
#include "fit/surface_landmarks.h"

namespace lorgnette::fit {

double FitResult::total_seconds() const {
  double s = 0.0;
  for (const auto& [name, t] : seconds) s += t;
  return s;
}

namespace {

using Clock = std::chrono::steady_clock;

struct StageTimer {
  FitResult& r;
  const char* name;
  Clock::time_point start = Clock::now();
  ~StageTimer() { r.seconds.emplace_back(name, std::chrono::duration<double>(Clock::now() - start).count()); }
};

std::string yaw_list(const std::vector<ViewRecord>& views, bool found) {
  std::vector<std::string> s;
  for (const auto& v : views)
    if (v.detection.found == found) s.push_back(fmt::format("{:.0f}/{:.0f}", v.yaw_deg, v.pitch_deg));
  return s.empty() ? "none" : fmt::format("{}", fmt::join(s, " "));
}

std::vector<ViewRecord> plan_and_detect(ViewSource& src, const LandmarkDetector& det, const Orbit& orbit,
                                        const FitOptions& opt) {
  std::vector<Eigen::Vector2d> angles = cap_angles(opt.cap);
  std::vector<Camera> cams;
  for (const auto& a : angles) cams.push_back(orbit_camera(orbit, a.x(), a.y()));
  std::vector<ViewRecord> views = detect_views(src, det, cams, opt);
  for (size_t i = 0; i < views.size(); ++i) views[i].yaw_deg = angles[i].x(), views[i].pitch_deg = angles[i].y();
  int found = 0;
  for (const auto& v : views) found += v.detection.found;
  if (found < opt.min_views)
    throw std::runtime_error(fmt::format(
        "a face was found in only {} of {} views (need {}): yaw/pitch with a face: {}; without: {}. "
        "Try more views (--views), a smaller angular range, or a higher resolution",
        found, views.size(), opt.min_views, yaw_list(views, true), yaw_list(views, false)));
  return views;
}

NamedLandmark named(const TriangulatedPoint& p, double mm_per_unit) {
  NamedLandmark n;
  n.position = p.position;
  n.sigma_mm = p.sigma * mm_per_unit;
  n.residual_px = p.rms_reprojection_px;
  n.views = int(p.inliers.size());
  return n;
}

void require_points(const std::vector<TriangulatedPoint>& pts) {
  std::vector<std::string> missing;
  for (int i : {lm::kTempleR, lm::kTempleL, lm::kNoseBridgeTop, lm::kNoseBridge2, lm::kEyeOuterR, lm::kEyeOuterL})
    if (!pts[i].ok) missing.push_back(fmt::format("{} ({})", i, pts[i].why));
  if (!missing.empty())
    throw std::runtime_error(fmt::format(
        "could not triangulate the landmarks the placement needs: {}. Try more views or a wider yaw range",
        fmt::join(missing, "; ")));
}

// Named landmarks for placement.json and the ok verdict with its reasons.
void summarise(FitResult& r, const FitOptions& opt) {
  const double mpu = r.head.mm_per_unit;
  const auto& P = r.points;
  NamedLandmark nose = named(P[lm::kNoseBridgeTop], mpu);
  nose.position = r.f_c;
  nose.residual_px = 0.5 * (P[lm::kNoseBridgeTop].rms_reprojection_px + P[lm::kNoseBridge2].rms_reprojection_px);
  r.landmarks["nose"] = nose;
  r.landmarks["eye_l"] = named(P[lm::kEyeOuterL], mpu);
  r.landmarks["eye_r"] = named(P[lm::kEyeOuterR], mpu);
  r.landmarks["temple_l"] = named(P[lm::kTempleL], mpu);
  r.landmarks["temple_r"] = named(P[lm::kTempleR], mpu);
  NamedLandmark ear_l = r.landmarks["temple_l"], ear_r = r.landmarks["temple_r"];
  ear_l.position = r.ears.f_l;
  ear_r.position = r.ears.f_r;
  r.landmarks["ear_l"] = ear_l;
  r.landmarks["ear_r"] = ear_r;
  r.ok = true;
  // Residuals judge the triangulated points; the surface-cast contour (temples, ears) slides with
  // the view by nature and is reported, not judged.
  for (const char* name : {"nose", "eye_l", "eye_r"})
    if (const NamedLandmark& l = r.landmarks[name]; l.residual_px > opt.max_residual_px) {
      r.ok = false;
      r.warnings.push_back(fmt::format("{}: reprojection residual {:.1f} px > {:.1f}", name, l.residual_px, opt.max_residual_px));
    }
  // The front (rims, bridge, pads) must not clip: that is visible in every frontal view. The temples
  // flex: they are spread at the hinges (temple_fit.h) and fail only when that cannot clear them.
  if (r.contact.refined && r.contact.front_penetration_mm > opt.max_penetration_mm) {
    r.ok = false;
    r.warnings.push_back(fmt::format("the front of the frame still penetrates the face by {:.2f} mm",
                                     r.contact.front_penetration_mm));
  }
  if (r.temples.fitted) {
    for (int side : {+1, -1})
      if (const TempleSideFit& t = side > 0 ? r.temples.left : r.temples.right; t.spread_deg > 0.0)
        spdlog::info("fit: {} temple spread {:.2f} deg outwards: penetration {:.2f} -> {:.2f} mm",
                     side > 0 ? "left" : "right", t.spread_deg, t.penetration_before_mm, t.penetration_mm);
    std::vector<std::string> w = temple_warnings(r.temples);
    r.ok = r.ok && w.empty();
    r.warnings.insert(r.warnings.end(), w.begin(), w.end());
  } else if (r.contact.refined && r.contact.front_penetration_mm <= opt.max_penetration_mm &&
             r.contact.penetration_mm > opt.max_penetration_mm) {
    r.warnings.push_back(fmt::format("the temples pass {:.2f} mm into the head near the ears (rigid frame: the "
                                     "glasses have no hinges to spread them at)", r.contact.penetration_mm));
  }
}

}  // namespace

FitResult fit_glasses(ViewSource& source, const GlassesRefPoints& glasses, const FitOptions& opt) {
  FitResult r;
  Face68 mean_face = mean_face_or_builtin(opt.mean_face_path);
  const float surface = opt.surface_density > 0.0f ? opt.surface_density : source.surface_density();
  std::unique_ptr<LandmarkDetector> detector;
  {
    StageTimer t{r, "load_detector"};
    detector = opt.detect ? std::make_unique<LandmarkDetector>(opt.detect)
                          : std::make_unique<LandmarkDetector>(opt.detector);
  }
  {
    StageTimer t{r, "front"};
    FrontSearchOptions fo{opt.width, opt.height, opt.fov_y_deg, opt.sweep_views, opt.face_fraction,
                          surface};
    r.orbit = find_front(source, *detector, fo).orbit;
  }
  std::vector<bool> valid(lm::kCount);
  for (int pass = 0; pass < 2; ++pass) {
    {
      StageTimer t{r, pass == 0 ? "render_detect" : "render_detect_recentred"};
      r.views = plan_and_detect(source, *detector, r.orbit, opt);
    }
    {
      StageTimer t{r, pass == 0 ? "triangulate" : "triangulate_recentred"};
      r.points = triangulate_landmarks(r.views, opt.triangulate);
      if (opt.cast_contour) {
        SurfaceCastOptions so;
        so.max_yaw_deg = opt.contour_max_yaw_deg;
        so.side_tolerance = opt.contour_side_tolerance;
        so.opacity = opt.contour_opacity;
        so.density_threshold = surface;
        cast_surface_landmarks(source, r.views, r.orbit, so, r.points);
      }
      for (int k = 0; k < lm::kCount; ++k) valid[k] = r.points[k].ok;
      std::vector<Eigen::Vector3d> p;
      for (const auto& q : r.points) p.push_back(q.position);
      require_points(r.points);
      r.head = estimate_head_frame(p, valid, mean_face);
      if (opt.snap_to_skin) {
        snap_to_surface(source, r.views, opt.snap_reach_mm / r.head.mm_per_unit, surface,
                        r.points, lm::kTempleR, opt.cast_contour ? lm::kTempleL : -1);
        p.clear();
        for (const auto& q : r.points) p.push_back(q.position);
        r.head = estimate_head_frame(p, valid, mean_face);
      }
    }
    Eigen::Vector3d f = r.head.d_fwd - r.head.d_fwd.dot(r.orbit.up) * r.orbit.up;
    double off = std::acos(std::clamp(f.normalized().dot(r.orbit.front), -1.0, 1.0)) * 180.0 / M_PI;
    if (pass == 1 || off <= opt.recenter_deg) break;
    spdlog::info("fit: the face's front is {:.1f} deg off the view cap's centre: re-planning the views", off);
    r.orbit.front = f.normalized();
  }
  r.views_used = 0;
  for (const auto& v : r.views) r.views_used += v.detection.found;
  {
    StageTimer t{r, "place"};
    const auto& P = r.points;
    r.f_c = nose_point(P[lm::kNoseBridgeTop].position, P[lm::kNoseBridge2].position, opt.nose_blend);
    EarInputs ei{P[lm::kEyeOuterL].position, P[lm::kEyeOuterR].position, P[lm::kTempleL].position,
                 P[lm::kTempleR].position, r.head.d_up, r.head.d_fwd};
    r.ears = ear_points(ei, opt.alpha);
    PlaceInputs pi{r.f_c, r.ears.f_l, r.ears.f_r, ei.t_l, ei.t_r, r.head.mm_per_unit};
    r.placement = place_glasses(glasses, pi, opt.scale_policy);
  }
  if (opt.refine_contact && !opt.frame_points.empty()) {
    DensityFn density = [&source](const std::vector<Eigen::Vector3f>& p) { return source.density(p); };
    Eigen::Vector3d axis = 0.5 * (r.ears.f_l + r.ears.f_r);
    ContactOptions co = opt.contact;
    co.density_threshold = surface * opt.solid_factor;
    co.tip_z_mm = std::min(glasses.g_l.z(), glasses.g_r.z());
    const bool spread = opt.temples.enabled && glasses.has_hinges;
    // With hinges the temples are fitted by spreading them (below): the front that the slide along
    // d_fwd must clear ends where the spread takes over (the hinges plus its ramp), or a temple
    // touching the side of the head would push the whole frame off the nose.
    if (spread)
      co.front_z_mm = std::max(co.front_z_mm,
                               std::min(glasses.hinge_l.z(), glasses.hinge_r.z()) - opt.temples.ramp_mm);
    {
      StageTimer t{r, "contact"};
      r.contact = refine_contact(r.placement, opt.frame_points, density, r.head.d_fwd, r.head.d_up, axis,
                                 r.head.mm_per_unit, co);
    }
    if (spread) {  // spread the temples, then re-measure the frame
      StageTimer tt{r, "temples"};
      TempleFitInputs ti{r.placement.transform, glasses.hinge_l, glasses.hinge_r, axis, r.head.d_up,
                         r.head.mm_per_unit};
      r.temples = fit_temples(ti, opt.frame_points, density, co, opt.max_penetration_mm, opt.temples);
      measure_contact(r.contact, r.placement, opt.frame_points, mesh::bend_points(r.temples.bend, opt.frame_points),
                      density, r.head.d_up, axis, r.head.mm_per_unit, co);
    }
  }
  summarise(r, opt);
  if (!opt.debug_dir.empty()) write_debug_views(opt.debug_dir, r);
  return r;
}

}  // namespace lorgnette::fit
