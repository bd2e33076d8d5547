// The placement pipeline (paper Sec. 3.1 plus contact refinement) on any ViewSource: find the front
// of the head, render K views on a cap around it, detect 68 landmarks per view (dlib), triangulate
// them robustly (detect_views.h), align the mean face (d_fwd, mm per unit, PD), find the ear rests
// on the density (ear_root.h; Eq. 2-3 where it shows none), place the frame (scale, Kabsch, Eq. 4-5),
// let it rest on the skin and spread the temples where they would clip (temple_fit.h). Fatal problems
// (no face, too few views, degenerate geometry) throw std::runtime_error saying what was seen and
// what to try.
#pragma once
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fit/detect_views.h"
#include "fit/ear_root.h"
#include "fit/ears.h"
#include "fit/fit_advice.h"
#include "fit/front_search.h"
#include "fit/glasses_input.h"
#include "fit/hair.h"
#include "fit/head_frame.h"
#include "fit/input_checks.h"
#include "fit/iris_views.h"
#include "fit/landmarks_dlib.h"
#include "fit/place.h"
#include "fit/pupil_distance.h"
#include "fit/scale_chain.h"
#include "fit/surface_landmarks.h"
#include "fit/temple_depth.h"
#include "fit/temple_fit.h"
#include "fit/triangulate.h"
#include "fit/view_planning.h"
#include "fit/view_source.h"

namespace lorgnette::fit {

// Per stage (the stage names are those of FitResult::seconds).
struct DetectionOptions {  // "load_detector", "render_detect"
  DetectorOptions detector;
  DetectFn detect;    // non-empty: this detector instead of dlib's (landmarks_dlib.h)
  int min_views = 3;  // views with a face needed
};

struct LandmarkOptions {  // "triangulate": the 68 points in 3D
  TriangulateOptions triangulate;
  bool cast_contour = true;         // jaw contour (temples) by surface casting, not triangulation
  SurfaceCastOptions contour;       // the views and depth of those casts
  TempleDepthOptions temple_depth;  // ... then the temples at one depth (with cast_contour)
  bool snap_to_skin = true;         // move triangulated landmarks along their rays onto the skin
  double snap_reach_mm = 12.0;      // how far (estimated with the mean face's scale)
  double max_residual_px = 6.0;     // ok = false when a used landmark's RMS residual is above this
};

struct HeadOptions {           // the head frame ("triangulate") and the ears ("place")
  std::string mean_face_path;  // empty: the built-in mean face (mean_face.h)
  double recenter_deg = 8.0;   // re-plan the cap when d_fwd is further than this from its centre
  double alpha = 0.5;          // Eq. 3
  double nose_blend = 0.5;     // f_c between dlib 27 (0) and 28 (1)
  // f_c from 27 and 28 moved along their rays to this opacity depth (ray_surface.h; 0: the skin
  // density's first crossing, as the other landmarks). The first crossing stops at haze in front of
  // the nose; a lower level stops in front of the skin on room captures, whose skin the binary prior
  // makes thin (docs/fit.md, "The nose point"). The head frame keeps the first-crossing points.
  double nose_opacity = 0.5;
  // The ears from the head's density (ear_root.h) where it shows the crease above the ear's root;
  // Eq. 2-3 where it does not.
  EarRootOptions ear_root;
};

struct ScaleOptions {                // "scale": the metric scale's source (scale_chain.h)
  std::optional<CaptureScale> card;  // the capture's measured scale (the model's metadata.metric_scale)
  bool irises = true;                // measure the irises: the scale without a card, PD always
  IrisViewOptions iris;
  IrisScaleOptions iris_scale;
};

struct PlaceOptions {  // "place", "contact"
  // auto: true size with a card's or the irises' scale, stretch with the mean face's (scale_chain.h).
  ScalePolicy scale_policy = ScalePolicy::kAuto;
  bool refine_contact = true;
  ContactSearchOptions contact;
  // Contact and penetration count as solid only `solid_factor` x the skin (0.2 optical depth per NeRF
  // step, 18 % opacity per ~1.3 mm): the haze a short training leaves around a real capture (hair,
  // the sides of a frontal capture) then no longer blocks the frame. in2n-face: temples 25 deg and
  // still 4.75 mm in at 1x, 20 / 23 deg and clear at 5x; fangzhou-frontal: 15 mm slide and 5.5 mm
  // front penetration at 1x, 4 mm and 0 mm at 5x; the quick demo head: 12.75 -> 10.5 mm slide.
  float solid_factor = 5.0f;
  double max_penetration_mm = 0.5;  // the temples' allowed depth (their spread search clears to it)
  // The temples meet only what lies behind 0.5 opacity seen from outside (opaque.h): haze is not a head.
  bool opaque_head = true;
  // ok = false when the front still reaches deeper into the face after refinement (input_checks.h).
  double front_tolerance_mm = kFrontToleranceMm;
};

struct FitOptions {
  FrontSearchOptions front;  // "front": view size, field of view, framing (the cap inherits them)
  CapOptions cap;            // "render_detect": K views and the yaw/pitch range around the front
  DetectionOptions detection;
  LandmarkOptions landmarks;
  HeadOptions head;
  ScaleOptions scale;
  PlaceOptions place;
  TempleFitOptions temples;      // "temples": spread them where they clip (needs the glasses' hinges)
  HairOptions hair;              // ... against the head without its hair (hair.h)
  float surface_density = 0.0f;  // skin for framing, surface casts and contact; 0: the source's own
  std::string debug_dir;         // non-empty: write annotated views there
  // Called as each stage starts, with its name (those of FitResult::seconds): progress for a UI.
  std::function<void(const std::string& stage)> on_stage;
};

struct NamedLandmark {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double sigma_mm = 0.0;     // 1-sigma positional uncertainty (largest axis)
  double residual_px = 0.0;  // RMS reprojection error over the views used
  int views = 0;
};

struct FitResult {
  bool ok = false;
  std::vector<std::string> warnings;
  Placement placement;
  HeadFrame head;
  EarPoints ears;
  EarRoots ear_roots;  // the density's ear rests (found or why not); `ears` holds the points used
  Eigen::Vector3d f_c = Eigen::Vector3d::Zero();
  std::map<std::string, NamedLandmark> landmarks;  // nose eye_l eye_r temple_l temple_r ear_l ear_r
  std::vector<TriangulatedPoint> points;           // all 68
  // The outer eye corners (45, 36) moved to their nearest skin (snap_to_surface's `nearest`), where the
  // advice measures the face's width at the temples: `points` holds them snapped along the mean ray
  // with the other landmarks (zero: not snapped, the advice then uses `points`).
  Eigen::Vector3d corner_skin_l = Eigen::Vector3d::Zero(), corner_skin_r = Eigen::Vector3d::Zero();
  ContactResult contact;
  Orbit orbit;                                          // the final view plan
  std::vector<ViewRecord> views;                        // the final cap
  int views_used = 0;                                   // views with a face
  std::vector<std::pair<std::string, double>> seconds;  // per stage, in order
  TempleFitResult temples;                              // the temple spread after the contact refinement
  std::optional<SkinTone> skin;    // the skin's tone the hair test used (none: hair counted as solid)
  TempleDepthResult temple_depth;  // whether a temple was moved to the other's depth, and how far
  std::vector<InputCheck> checks;  // the inputs checked and the verdict's tolerances (input_checks.h)
  // The metric scale (head.mm_per_unit is its figure; scale.mean_face_mm_per_unit the mean face's),
  // the iris measurements behind it, PD's 1-sigma, the policy the frame was placed with and the advice.
  MetricScale scale;
  IrisScale iris;
  std::vector<IrisMeasurement> iris_measurements;
  PupilDistance pupils;  // PD from the limbus centres (or why not: PD then from the eyes' landmarks)
  double pd_uncertainty_mm = 0.0;
  ScalePolicy scale_policy = ScalePolicy::kStretch;
  FitAdvice advice;
  Placement advice_placement;  // the frame the advice measures: true size, resting on the head
  double total_seconds() const;
};

// The lower-level entry on any ViewSource (the mesh in tests and benchmarks); run_fit_job
// (fit_job.h) is the whole job on a NeRF. Without frame points the contact and temple stages are
// skipped.
FitResult fit_glasses(ViewSource& source, const GlassesInput& glasses, const FitOptions& options);

// What detect_views (detect_views.h) reads of the fit's options.
ViewDetectOptions view_detect_options(const FitOptions& options);

}  // namespace lorgnette::fit
