// The placement pipeline (see fit.h).
#include "fit/fit.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <stdexcept>

#include "fit/advice_geometry.h"
#include "fit/camera_math.h"
#include "fit/debug_draw.h"
#include "fit/front_search.h"
#include "fit/landmark_ids.h"
#include "fit/mean_face.h"
#include "fit/opaque.h"
#include "fit/surface_landmarks.h"

namespace lorgnette::fit {

ViewDetectOptions view_detect_options(const FitOptions& o) {
  return {o.detection.detector, o.front.face_fraction, !o.debug_dir.empty()};
}

double FitResult::total_seconds() const {
  double s = 0.0;
  for (const auto& [name, t] : seconds) s += t;
  return s;
}

namespace {

using Clock = std::chrono::steady_clock;

// Times a stage into FitResult::seconds and tells FitOptions::on_stage that it starts.
struct StageTimer {
  FitResult& r;
  const char* name;
  Clock::time_point start = Clock::now();
  StageTimer(FitResult& result, const char* stage, const FitOptions& o) : r(result), name(stage) {
    if (o.on_stage) o.on_stage(stage);
  }
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
  std::vector<Camera> cams = cap_cameras(orbit, opt.cap);
  std::vector<ViewRecord> views = detect_views(src, det, cams, view_detect_options(opt));
  for (size_t i = 0; i < views.size(); ++i)
    views[i].yaw_deg = angles[i].x(), views[i].pitch_deg = angles[i].y();
  int found = 0;
  for (const auto& v : views) found += v.detection.found;
  if (found < opt.detection.min_views)
    throw std::runtime_error(fmt::format(
        "a face was found in only {} of {} views (need {}): yaw/pitch with a face: {}; without: {}. "
        "Try more views (--views), a smaller angular range, or a higher resolution",
        found, views.size(), opt.detection.min_views, yaw_list(views, true), yaw_list(views, false)));
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
  for (int i :
       {lm::kTempleR, lm::kTempleL, lm::kNoseBridgeTop, lm::kNoseBridge2, lm::kEyeOuterR, lm::kEyeOuterL})
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
  nose.residual_px =
      0.5 * (P[lm::kNoseBridgeTop].rms_reprojection_px + P[lm::kNoseBridge2].rms_reprojection_px);
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
    if (const NamedLandmark& l = r.landmarks[name]; l.residual_px > opt.landmarks.max_residual_px) {
      r.ok = false;
      r.warnings.push_back(fmt::format("{}: reprojection residual {:.1f} px > {:.1f}", name, l.residual_px,
                                       opt.landmarks.max_residual_px));
    }
  // The front (rims, bridge, pads) must not clip beyond its tolerance: that is visible in every
  // frontal view. The temples flex: they are spread at the hinges (temple_fit.h) and fail when that
  // cannot clear them, or needs more spread than a worn frame takes (input_checks.h).
  r.checks.push_back(check_front_penetration(r.contact.refined, r.contact.front_penetration_mm,
                                             opt.place.front_tolerance_mm));
  r.checks.push_back(check_temple_spread(r.temples, !r.ear_roots.from_density()));
  for (const InputCheck& c : r.checks)
    if (!c.passed) {
      r.ok = false;
      r.warnings.push_back(c.reason);
    }
  if (r.temples.fitted) {
    for (int side : {+1, -1})
      if (const TempleSideFit& t = side > 0 ? r.temples.left : r.temples.right; t.spread_deg > 0.0)
        spdlog::info("fit: {} temple spread {:.2f} deg outwards: penetration {:.2f} -> {:.2f} mm",
                     side > 0 ? "left" : "right", t.spread_deg, t.penetration_before_mm, t.penetration_mm);
    std::vector<std::string> w = temple_warnings(r.temples);
    r.ok = r.ok && w.empty();
    r.warnings.insert(r.warnings.end(), w.begin(), w.end());
  } else if (r.contact.refined && r.contact.front_penetration_mm <= opt.place.front_tolerance_mm &&
             r.contact.penetration_mm > opt.place.max_penetration_mm) {
    r.warnings.push_back(
        fmt::format("the temples pass {:.2f} mm into the head near the ears (rigid frame: the "
                    "glasses have no hinges to spread them at)",
                    r.contact.penetration_mm));
  }
}

// What the stages share: the inputs, the skin's density and the result they fill in.
struct FitRun {
  FitRun(ViewSource& source_, const GlassesInput& glasses_, const FitOptions& opt_, float surface_,
         FitResult& r_, Face68 mean_face_)
      : source(source_),
        glasses(glasses_),
        opt(opt_),
        surface(surface_),
        r(r_),
        mean_face(std::move(mean_face_)) {}
  ViewSource& source;
  const GlassesInput& glasses;
  const FitOptions& opt;
  float surface = 0.0f;  // FitOptions::surface_density, else the source's own
  FitResult& r;
  std::unique_ptr<LandmarkDetector> detector;
  Face68 mean_face;
  ColourFn colour = [this](const std::vector<Eigen::Vector3f>& p, const std::vector<Eigen::Vector3f>& d) {
    return source.colour(p, d);
  };
  bool skin_read = false;  // r.skin holds the nose line's tone (face_skin)
  EarPoints eq23_ears{};   // Eq. 2-3's ears, kept for ears_back_to_eq23
  // The density's ear rests when the placement went back to Eq. 2-3's: still where a temple rests,
  // so the advice measures the temples to them.
  std::optional<EarPoints> rest_ears;
};

void load_detector(FitRun& run) {
  StageTimer t{run.r, "load_detector", run.opt};
  const DetectionOptions& o = run.opt.detection;
  run.detector = o.detect ? std::make_unique<LandmarkDetector>(o.detect)
                          : std::make_unique<LandmarkDetector>(o.detector);
}

void find_front(FitRun& run) {
  StageTimer t{run.r, "front", run.opt};
  run.r.orbit = fit::find_front(run.source, *run.detector, run.opt.front, run.surface).orbit;
}

std::vector<Eigen::Vector3d> positions(const std::vector<TriangulatedPoint>& points) {
  std::vector<Eigen::Vector3d> p;
  for (const auto& q : points) p.push_back(q.position);
  return p;
}

// The 68 points: triangulated, the jaw contour cast onto the skin.
void triangulate_and_cast(FitRun& run) {
  const LandmarkOptions& o = run.opt.landmarks;
  FitResult& r = run.r;
  r.points = triangulate_landmarks(r.views, o.triangulate);
  if (o.cast_contour) cast_surface_landmarks(run.source, r.views, r.orbit, o.contour, run.surface, r.points);
}

// The mean face aligned to the points (and again after they are snapped onto the skin), then the
// temples at one depth (temple_depth.h). The advice's outer eye corners are the triangulated ones
// moved to their nearest skin (surface_landmarks.h), not along the mean ray as the others.
void estimate_head(FitRun& run) {
  const LandmarkOptions& o = run.opt.landmarks;
  FitResult& r = run.r;
  std::vector<bool> valid(lm::kCount);
  for (int k = 0; k < lm::kCount; ++k) valid[k] = r.points[k].ok;
  std::vector<Eigen::Vector3d> p = positions(r.points);
  require_points(r.points);
  r.head = estimate_head_frame(p, valid, run.mean_face);
  if (o.snap_to_skin) {
    std::vector<TriangulatedPoint> corners = {r.points[lm::kEyeOuterL], r.points[lm::kEyeOuterR]};
    snap_to_surface(run.source, r.views, o.snap_reach_mm / r.head.mm_per_unit, run.surface, corners, -1, -1,
                    0.0, true);
    r.corner_skin_l = corners[0].position, r.corner_skin_r = corners[1].position;
    snap_to_surface(run.source, r.views, o.snap_reach_mm / r.head.mm_per_unit, run.surface, r.points,
                    lm::kTempleR, o.cast_contour ? lm::kTempleL : -1);
    r.head = estimate_head_frame(positions(r.points), valid, run.mean_face);
  }
  if (!o.cast_contour) return;            // balance_temple_depths reads the casts' view indices
  if (run.source.hard_surface()) return;  // exact surfaces are never soft (temple_depth.h)
  r.temple_depth = balance_temple_depths(run.source, r.views, r.head, o.temple_depth, r.points);
  if (r.temple_depth.moved != 0)
    spdlog::info("fit: {}", r.temple_depth.summary());
  else
    spdlog::debug("fit: {}", r.temple_depth.summary());
}

// The cap of views, its landmarks and the head frame; once more on a re-centred cap when the face's
// front is off the first cap's centre.
void plan_detect_and_frame_head(FitRun& run) {
  FitResult& r = run.r;
  for (int pass = 0; pass < 2; ++pass) {
    {
      StageTimer t{r, pass == 0 ? "render_detect" : "render_detect_recentred", run.opt};
      r.views = plan_and_detect(run.source, *run.detector, r.orbit, run.opt);
    }
    {
      StageTimer t{r, pass == 0 ? "triangulate" : "triangulate_recentred", run.opt};
      triangulate_and_cast(run);
      estimate_head(run);
    }
    Eigen::Vector3d f = r.head.d_fwd - r.head.d_fwd.dot(r.orbit.up) * r.orbit.up;
    double off = std::acos(std::clamp(f.normalized().dot(r.orbit.front), -1.0, 1.0)) * 180.0 / M_PI;
    if (pass == 1 || off <= run.opt.head.recenter_deg) break;
    spdlog::info("fit: the face's front is {:.1f} deg off the view cap's centre: re-planning the views", off);
    r.orbit.front = f.normalized();
  }
  r.views_used = 0;
  for (const auto& v : r.views) r.views_used += v.detection.found;
}

// The skin's tone from the nose line (hair.h), once: the ears' and the temples' hair tests read it.
const std::optional<SkinTone>& face_skin(FitRun& run) {
  FitResult& r = run.r;
  if (run.skin_read) return r.skin;
  run.skin_read = true;
  std::vector<Eigen::Vector3d> nose_line;
  for (int k = lm::kNoseBridgeTop; k <= lm::kNoseTip; ++k)
    if (r.points[k].ok) nose_line.push_back(r.points[k].position);
  r.skin = skin_tone(run.colour, nose_line, -r.head.d_fwd);
  return r.skin;
}

// The ears where the density shows the crease above each ear's root (ear_root.h), instead of Eq.
// 2-3. A side whose ear top is as dark as hair (hair.h's test, seen from above) is not an ear: the
// two real captures' hair made creases of its own.
void ears_from_density(FitRun& run, const EarInputs& ei) {
  FitResult& r = run.r;
  ViewSource& source = run.source;
  DensityFn density = [&source](const std::vector<Eigen::Vector3f>& p) { return source.density(p); };
  const std::optional<SkinTone> none, &skin = run.opt.hair.enabled ? face_skin(run) : none;
  EarVeto hair_dark = [&](const EarRootSide& s) -> std::string {
    if (!skin || s.ear_top.empty()) return {};
    const std::optional<double> median = ear_top_luminance(run.colour, s.ear_top, r.head.d_up);
    if (!median) return {};
    const double darkest = run.opt.hair.max_luminance_ratio * skin->luminance;
    spdlog::debug("fit: an ear's top at {:.2f} x the skin's luminance", *median / skin->luminance);
    if (*median >= darkest) return {};
    return fmt::format("its top is as dark as hair (luminance {:.3f}, under {:.3f} = {:.2f} x the skin's)",
                       *median, darkest, run.opt.hair.max_luminance_ratio);
  };
  r.ear_roots = apply_ear_roots(density, ei, r.head.d_eye, r.head.mm_per_unit, run.opt.head.ear_root, r.ears,
                                hair_dark);
  spdlog::info("fit: {}", r.ear_roots.summary());
}

// Eq. 4-5 from the nose point, the ears and the temples as they stand in the result.
void place_from_points(FitRun& run) {
  FitResult& r = run.r;
  PlaceInputs pi{r.f_c,
                 r.ears.f_l,
                 r.ears.f_r,
                 r.points[lm::kTempleL].position,
                 r.points[lm::kTempleR].position,
                 r.head.mm_per_unit};
  r.placement = place_glasses(run.glasses.ref, pi, r.scale_policy);
}

// The six landmarks of the eye whose first dlib index is `first`; false when one is not triangulated.
bool eye_contour(const std::vector<TriangulatedPoint>& P, int first, EyeContour* eye) {
  for (int k = 0; k < 6; ++k) {
    if (!P[first + k].ok) return false;
    (*eye)[k] = P[first + k].position;
  }
  return true;
}

// The mean of an eye's triangulated landmarks (its centre, the pupil's stand-in) and their mean sigma.
Eigen::Vector3d eye_centre(const std::vector<TriangulatedPoint>& P, int first, double* sigma = nullptr) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  double s = 0;
  int n = 0;
  for (int k = first; k < first + 6; ++k)
    if (P[k].ok) c += P[k].position, s += P[k].sigma, ++n;
  if (sigma) *sigma = n ? s / n : 0.0;
  return n ? Eigen::Vector3d(c / n) : P[first].position;
}

// The distance from the eyes to the camera of the view with a face nearest the cap's centre: the
// iris views look from as far as the capture did.
double iris_view_distance(const FitResult& r, const Eigen::Vector3d& eyes) {
  double best = 1e30, dist = 0.0;
  for (const ViewRecord& v : r.views)
    if (const double off = std::hypot(v.yaw_deg, v.pitch_deg); v.detection.found && off < best)
      best = off, dist = (camera_center(v.camera) - eyes).norm();
  return dist;
}

// The irises measured (iris_views.h) when the eyes' landmarks are all there, or the reason they are
// not (then in r.iris.why).
void measure_iris_views(FitRun& run) {
  FitResult& r = run.r;
  EyeContour left, right;
  if (!eye_contour(r.points, lm::kEyeLFirst, &left) || !eye_contour(r.points, lm::kEyeRFirst, &right)) {
    r.iris.why = "the eyes' landmarks were not all triangulated";
    return;
  }
  const Eigen::Vector3d eyes =
      0.5 * (eye_centre(r.points, lm::kEyeLFirst) + eye_centre(r.points, lm::kEyeRFirst));
  r.iris_measurements = measure_irises(run.source, left, right, r.head.d_up, r.head.d_fwd,
                                       iris_view_distance(r, eyes), run.opt.scale.iris);
}

// PD in scene units and each eye centre's 1-sigma along the eyes' line: from the limbus centres
// (pupil_distance.h) when both eyes' were found, else from the eyes' landmarks (the mean of six,
// whose sigma is along their worst axis, mostly depth, which PD does not see: sigma / sqrt(6) each).
double pd_units(FitResult& r, double* sigma_l, double* sigma_r) {
  r.pupils = pupil_distance(r.iris_measurements);
  if (r.pupils.ok) {
    *sigma_l = r.pupils.sigma_left, *sigma_r = r.pupils.sigma_right;
    return r.pupils.units;
  }
  eye_centre(r.points, lm::kEyeLFirst, sigma_l), eye_centre(r.points, lm::kEyeRFirst, sigma_r);
  *sigma_l /= std::sqrt(6.0), *sigma_r /= std::sqrt(6.0);
  return r.head.pd_mm / r.head.mm_per_unit;
}

// The irises (their size for the scale when there is no card, their centres for PD either way), the
// scale's source (scale_chain.h) and the policy it implies; the head's mm per unit and PD then follow
// the chosen scale.
void measure_scale(FitRun& run) {
  StageTimer t{run.r, "scale", run.opt};
  FitResult& r = run.r;
  const ScaleOptions& o = run.opt.scale;
  const double mean_face = r.head.mm_per_unit;
  if (o.irises) measure_iris_views(run);
  const IrisScale* iris = nullptr;
  if (!o.card && o.irises) {
    if (!r.iris_measurements.empty()) r.iris = iris_scale(r.iris_measurements, mean_face, o.iris_scale);
    iris = &r.iris;
  }
  r.scale = choose_scale(o.card, iris, mean_face);
  double sigma_l = 0, sigma_r = 0;
  const double pd = pd_units(r, &sigma_l, &sigma_r);
  r.head.pd_mm = pd * r.scale.mm_per_unit;
  r.head.mm_per_unit = r.scale.mm_per_unit;
  r.pd_uncertainty_mm = pd_uncertainty_mm(r.head.pd_mm, r.scale.relative_uncertainty(),
                                          sigma_l * r.scale.mm_per_unit, sigma_r * r.scale.mm_per_unit);
  r.scale_policy = resolve_scale_policy(run.opt.place.scale_policy, r.scale.source);
  spdlog::info(
      "fit: scale from {}: {:.4g} +- {:.2g} mm per unit (mean face {:.4g}); PD {:.1f} +- {:.1f} mm (from "
      "{}); {}",
      scale_source_name(r.scale.source), r.scale.mm_per_unit, r.scale.mm_per_unit_uncertainty, mean_face,
      r.head.pd_mm, r.pd_uncertainty_mm,
      r.pupils.ok ? "the limbus centres" : "the eyes' landmarks: " + r.pupils.why, r.scale.why);
  if (r.scale_policy == ScalePolicy::kStretch)
    r.warnings.push_back(fmt::format(
        "the frame is stretched to the face's width: the size shown is not its real size (scale: {})",
        r.scale.why));
  else if (r.scale.source == ScaleSource::kMeanFace)
    r.warnings.push_back("true size with an approximate scale: " + r.scale.why);
}

HeadProbe make_head_probe(const FitRun& run);

// Why the lens height cannot take the limbus centres (empty when it can).
std::string why_no_limbus(const FitRun& run) {
  const FitResult& r = run.r;
  if (r.pupils.ok) return "";
  if (!run.opt.scale.irises) return "the irises were not measured";
  if (r.iris_measurements.empty() && !r.iris.why.empty()) return r.iris.why;
  return r.pupils.why;
}

// The fit advice (fit_advice.h) for the frame at true size as it rests on the head.
void advise(FitRun& run) {
  StageTimer t{run.r, "advice", run.opt};
  FitResult& r = run.r;
  const auto& P = r.points;
  // The temples are measured to the ears' rests: the density's, whether or not the placement kept
  // them. Eq. 2-3's ears are a point for the frame's turn, 20-40 mm off the ear (ear_root.h).
  const EarPoints& ears = r.ear_roots.from_density() || !run.rest_ears ? r.ears : *run.rest_ears;
  const bool rests = r.ear_roots.from_density() || run.rest_ears.has_value();
  AdviceHead h{eye_centre(P, lm::kEyeLFirst),
               eye_centre(P, lm::kEyeRFirst),
               ears.f_l,
               ears.f_r,
               r.corner_skin_l.isZero() ? P[lm::kEyeOuterL].position : r.corner_skin_l,
               r.corner_skin_r.isZero() ? P[lm::kEyeOuterR].position : r.corner_skin_r,
               r.head.mm_per_unit,
               r.scale.source == ScaleSource::kMeanFace,
               r.pupils.ok,
               r.pupils.left,
               r.pupils.right,
               why_no_limbus(run)};
  const PlaceInputs points{
      r.f_c, r.ears.f_l, r.ears.f_r, P[lm::kTempleL].position, P[lm::kTempleR].position, r.head.mm_per_unit};
  const bool rest = run.opt.place.refine_contact && !run.glasses.frame_points.empty();
  const HeadProbe probe = make_head_probe(run);
  r.advice_placement = advice_placement(run.glasses.ref, points, r.scale_policy, r.placement,
                                        rest ? &probe : nullptr, r.head.d_fwd);
  ViewSource& source = run.source;
  DensityFn density = [&source](const std::vector<Eigen::Vector3f>& p) { return source.density(p); };
  AdviceInputs in = advice_inputs(run.glasses, r.advice_placement, h, density, run.surface);
  if (!rests && in.hinge_to_ear_mm > 0) {
    in.hinge_to_ear_mm = 0.0;
    in.why_no_hinges =
        "the ears' rests were not found on the head (Eq. 2-3's estimate lies 20-40 mm off the ear)";
  }
  r.advice = fit_advice(in);
  for (const AdviceRule& a : r.advice.rules) spdlog::info("fit advice: {}", a.text);
}

// The nose point, the ears (Eq. 2-3, or the density's, above) and the placement (Eq. 4-5).
void place_on_face(FitRun& run) {
  StageTimer t{run.r, "place", run.opt};
  FitResult& r = run.r;
  const HeadOptions& o = run.opt.head;
  const auto& P = r.points;
  r.f_c = nose_point(P[lm::kNoseBridgeTop].position, P[lm::kNoseBridge2].position, o.nose_blend);
  if (o.nose_opacity > 0.0) {  // the two bridge points alone, onto the opacity depth
    std::vector<TriangulatedPoint> bridge = P;
    for (int k = 0; k < lm::kCount; ++k) bridge[k].ok = k == lm::kNoseBridgeTop || k == lm::kNoseBridge2;
    snap_to_surface(run.source, r.views, run.opt.landmarks.snap_reach_mm / r.head.mm_per_unit, run.surface,
                    bridge, -1, -1, o.nose_opacity);
    r.f_c = nose_point(bridge[lm::kNoseBridgeTop].position, bridge[lm::kNoseBridge2].position, o.nose_blend);
  }
  EarInputs ei{P[lm::kEyeOuterL].position,
               P[lm::kEyeOuterR].position,
               P[lm::kTempleL].position,
               P[lm::kTempleR].position,
               r.head.d_up,
               r.head.d_fwd};
  r.ears = run.eq23_ears = ear_points(ei, o.alpha);
  if (o.ear_root.enabled) ears_from_density(run, ei);
  place_from_points(run);
}

// The density's ears lie at the ear's root, higher than Eq. 2-3's eye height, and the frame tilts
// forward with them. Where its front then cannot clear the face within the contact's range (the
// rims would rest on the cheeks: a small or soft head, a deep frame), Eq. 2-3's ears are used and
// the frame is placed again.
void ears_back_to_eq23(FitRun& run) {
  FitResult& r = run.r;
  if (r.ear_roots.from_density()) run.rest_ears = r.ears;
  const std::string why = fmt::format(
      "with them the frame's front still passes {:.2f} mm into the face after the contact search; the ears "
      "from Eq. 2-3 instead",
      r.contact.front_penetration_mm);
  spdlog::info("fit: the density's ears: {}", why);
  r.ear_roots.left.found = r.ear_roots.right.found = false;
  r.ear_roots.left.why = r.ear_roots.right.why = why;
  r.ear_roots.use = EarRoots::Use::kEq23;
  r.ears = run.eq23_ears;
  place_from_points(run);
  r.temples = {};
}

bool spreads_temples(const FitRun& run) { return run.opt.temples.enabled && run.glasses.ref.has_hinges; }

// Contact counts `solid_factor` x the skin as solid; the temple tips begin at the ear rests. With
// hinges the temples are fitted by spreading them: the front that the slide along d_fwd must clear
// ends where the spread takes over (the hinges plus its ramp), or a temple touching the side of the
// head would push the whole frame off the nose.
HeadProbe make_head_probe(const FitRun& run) {
  const GlassesRefPoints& g = run.glasses.ref;
  const FitResult& r = run.r;
  ContactSearchOptions search = run.opt.place.contact;
  if (spreads_temples(run))
    search.front_z_mm =
        std::max(search.front_z_mm, std::min(g.hinge_l.z(), g.hinge_r.z()) - run.opt.temples.ramp_mm);
  ViewSource& source = run.source;
  return HeadProbe{
      [&source](const std::vector<Eigen::Vector3f>& p) { return source.density(p); },
      0.5 * (r.ears.f_l + r.ears.f_r),
      r.head.d_up,
      r.head.mm_per_unit,
      ContactOptions{search, run.surface * run.opt.place.solid_factor, std::min(g.g_l.z(), g.g_r.z())},
      run.glasses.frame_points};
}

void rest_on_skin(FitRun& run, const HeadProbe& head, const char* stage = "contact") {
  StageTimer t{run.r, stage, run.opt};
  run.r.contact = refine_contact(run.r.placement, head, run.r.head.d_fwd);
}

// The head as the temples meet it: hair removed (hair.h) when the source has colour and the nose
// line gives the skin's tone, and haze that does not hide what lies behind it removed (opaque.h) when
// the source's surfaces are soft (a NeRF; exact meshes are neither hazy nor soft).
HeadProbe temple_probe(FitRun& run, const HeadProbe& head) {
  FitResult& r = run.r;
  HeadProbe skin = head;
  if (run.opt.hair.enabled && face_skin(run)) {
    spdlog::info(
        "fit: skin luminance {:.3f} from {} nose-line points; the temples ignore dense volume below {:.3f}",
        r.skin->luminance, r.skin->samples, run.opt.hair.max_luminance_ratio * r.skin->luminance);
    skin.density = density_without_hair(head, run.colour, *r.skin, run.opt.hair);
  } else if (run.opt.hair.enabled) {
    spdlog::info("fit: no skin colour from this head (a source without colour): hair counts as solid");
  }
  if (run.opt.place.opaque_head && !run.source.hard_surface())
    skin.density = density_behind_opacity(head, skin.density);
  return skin;
}

// Spreads the temples against the head without its hair, then re-measures the frame on it.
void spread_temples(FitRun& run, const HeadProbe& head, const char* stage = "temples") {
  StageTimer t{run.r, stage, run.opt};
  FitResult& r = run.r;
  const HeadProbe skin = temple_probe(run, head);
  TempleFitInputs ti{r.placement.transform, run.glasses.ref.hinge_l, run.glasses.ref.hinge_r};
  r.temples = fit_temples(ti, skin, run.opt.place.max_penetration_mm, run.opt.temples);
  measure_contact(r.contact, r.placement, skin, mesh::bend_points(r.temples.bend, skin.frame_points));
}

// The head the frame is placed on, checked before the verdict (input_checks.h): the nose line's skin
// and whether the face's landmarks lie on density.
void check_inputs(FitRun& run) {
  StageTimer t{run.r, "checks", run.opt};
  FitResult& r = run.r;
  std::vector<Eigen::Vector3d> nose_line;
  for (int k = lm::kNoseBridgeTop; k <= lm::kNoseTip; ++k)
    if (r.points[k].ok) nose_line.push_back(r.points[k].position);
  r.checks.push_back(check_nose_skin(run.colour, nose_line, -r.head.d_fwd));
  std::vector<Camera> cameras;
  for (const ViewRecord& v : r.views) cameras.push_back(v.camera);
  ViewSource& source = run.source;
  DensityFn density = [&source](const std::vector<Eigen::Vector3f>& p) { return source.density(p); };
  r.checks.push_back(check_landmarks_solid(density, cameras, r.points, r.head.mm_per_unit));
}

}  // namespace

FitResult fit_glasses(ViewSource& source, const GlassesInput& glasses, const FitOptions& opt) {
  FitResult r;
  const float surface = opt.surface_density > 0.0f ? opt.surface_density : source.surface_density();
  FitRun run(source, glasses, opt, surface, r, mean_face_or_builtin(opt.head.mean_face_path));
  load_detector(run);
  find_front(run);
  plan_detect_and_frame_head(run);
  measure_scale(run);
  place_on_face(run);
  if (opt.place.refine_contact && !glasses.frame_points.empty()) {
    auto rest_and_spread = [&](const char* contact_stage, const char* temples_stage) {
      const HeadProbe head = make_head_probe(run);
      rest_on_skin(run, head, contact_stage);
      if (spreads_temples(run)) spread_temples(run, head, temples_stage);
    };
    rest_and_spread("contact", "temples");
    if (r.ear_roots.from_density() && r.contact.front_penetration_mm > opt.place.max_penetration_mm) {
      ears_back_to_eq23(run);
      rest_and_spread("contact_eq23_ears", "temples_eq23_ears");
    }
  }
  advise(run);
  check_inputs(run);
  summarise(r, opt);
  if (!opt.debug_dir.empty()) write_debug_views(opt.debug_dir, r.views, r.points);
  return r;
}

}  // namespace lorgnette::fit
