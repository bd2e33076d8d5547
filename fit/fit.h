// The placement pipeline (paper Sec. 3.1 plus contact refinement) on any ViewSource: find the front
// of the head, render K views on a cap around it, detect 68 landmarks per view (dlib), triangulate
// them robustly, align the mean face (d_fwd, mm per unit, PD), estimate the ears (Eq. 2-3), place
// the frame (scale, Kabsch, Eq. 4-5), let it rest on the skin and spread the temples where they
// would clip (temple_fit.h). Fatal problems (no face, too few views, degenerate geometry) throw
// std::runtime_error saying what was seen and what to try.
#pragma once
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "fit/ears.h"
#include "fit/head_frame.h"
#include "fit/landmarks_dlib.h"
#include "fit/place.h"
#include "fit/temple_fit.h"
#include "fit/triangulate.h"
#include "fit/view_planning.h"
#include "fit/view_source.h"

namespace lorgnette::fit {

struct FitOptions {
  CapOptions cap;                     // K views and the yaw/pitch range around the front
  int width = 384, height = 384;      // view resolution (pixels)
  double fov_y_deg = 25.0;
  double face_fraction = 0.5;         // face box width / image width after framing
  int sweep_views = 8;                // yaw steps of the front search (when the prior has no front)
  double recenter_deg = 8.0;          // re-plan the cap when d_fwd is further than this from its centre
  DetectorOptions detector;
  DetectFn detect;                    // non-empty: this detector instead of dlib's (landmarks_dlib.h)
  TriangulateOptions triangulate;
  int min_views = 3;                  // views with a face needed
  bool cast_contour = true;           // jaw contour (temples) by surface casting, not triangulation
  double contour_max_yaw_deg = 25.0;  // views used for that
  double contour_side_tolerance = 0.025;  // ... and only those that show the landmark's side (surface_landmarks.h)
  double contour_opacity = 0.5;       // a contour ray's surface point: opacity reached (0: first density crossing)
  bool snap_to_skin = true;           // move triangulated landmarks along their rays onto the skin
  double snap_reach_mm = 12.0;        // how far (estimated with the mean face's scale)
  double detector_noise_px = 0.0;     // added Gaussian noise on 2D landmarks (stability study)
  unsigned seed = 1;
  std::string mean_face_path;         // empty: the built-in mean face (mean_face.h)
  double alpha = 0.5;                 // Eq. 3
  double nose_blend = 0.5;            // f_c between dlib 27 (0) and 28 (1)
  ScalePolicy scale_policy = ScalePolicy::kStretch;
  bool refine_contact = true;
  ContactOptions contact;              // its density_threshold is replaced by surface_density below
  float surface_density = 0.0f;        // skin for the surface casts and framing; 0: the source's own
  // Contact and penetration count as solid only `solid_factor` x that (0.2 optical depth per NeRF step,
  // 18 % opacity per ~1.3 mm): the haze a short training leaves around a real capture (hair, the sides
  // of a frontal capture) then no longer blocks the frame. in2n-face: temples 25 deg and still 4.75 mm
  // in at 1x, 20 / 23 deg and clear at 5x; fangzhou-frontal: 15 mm slide and 5.5 mm front penetration
  // at 1x, 4 mm and 0 mm at 5x; the quick demo head: 12.75 -> 10.5 mm slide.
  float solid_factor = 5.0f;
  std::vector<Eigen::Vector3d> frame_points;  // canonical-mm samples of the frame (contact, penetration)
  double max_penetration_mm = 0.5;    // ok = false above this after refinement
  double max_residual_px = 6.0;       // ok = false when a used landmark's RMS residual is above this
  std::string debug_dir;              // non-empty: write annotated views there
  TempleFitOptions temples;           // spread the temples where they clip (needs the glasses' hinges)
};

struct NamedLandmark {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double sigma_mm = 0.0;       // 1-sigma positional uncertainty (largest axis)
  double residual_px = 0.0;    // RMS reprojection error over the views used
  int views = 0;
};

struct ViewRecord {
  Camera camera{};
  double yaw_deg = 0.0, pitch_deg = 0.0;
  FaceDetection detection;
  Image image;  // the rendered view, kept only when FitOptions::debug_dir is set
};

struct FitResult {
  bool ok = false;
  std::vector<std::string> warnings;
  Placement placement;
  HeadFrame head;
  EarPoints ears;
  Eigen::Vector3d f_c = Eigen::Vector3d::Zero();
  std::map<std::string, NamedLandmark> landmarks;  // nose eye_l eye_r temple_l temple_r ear_l ear_r
  std::vector<TriangulatedPoint> points;           // all 68
  ContactResult contact;
  Orbit orbit;                                     // the final view plan
  std::vector<ViewRecord> views;                   // the final cap
  int views_used = 0;                              // views with a face
  std::vector<std::pair<std::string, double>> seconds;  // per stage, in order
  TempleFitResult temples;                         // the temple spread after the contact refinement
  double total_seconds() const;
};

FitResult fit_glasses(ViewSource& source, const GlassesRefPoints& glasses, const FitOptions& options);

// Renders and detects every view of `cameras` (with the noise of `options`).
std::vector<ViewRecord> detect_views(ViewSource& source, const LandmarkDetector& detector,
                                     const std::vector<Camera>& cameras, const FitOptions& options);

// Triangulates the 68 landmarks from the views with a face.
std::vector<TriangulatedPoint> triangulate_landmarks(const std::vector<ViewRecord>& views,
                                                     const TriangulateOptions& options);

}  // namespace lorgnette::fit
