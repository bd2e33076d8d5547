// Metric scale from the irises: the horizontal visible iris diameter (HVID, the limbus from side to
// side) varies little between adults, so its size in scene units gives millimetres per unit. The
// population figure is 11.7 mm with a spread (1 SD) of about 0.5 mm: Rüfer, Schröder & Erb,
// "White-to-white corneal diameter: normal values in healthy humans obtained with the Orbscan II
// topography system", Cornea 24(3):259-261, 2005 (457 eyes, 11.71 +- 0.42 mm); 0.5 mm is that SD
// rounded up for the visible edge being softer than the instrument's.
//
// Two layers: find_iris_edges() finds the limbus in one image of an eye (pure, tested on analytic
// discs); iris_scale() turns measurements from several views of both eyes into mm per unit with its
// uncertainty, or refuses with the reason (eyes closed, weak edges, the two eyes disagree), in which
// case the fit falls back to the mean face (scale_chain.h).
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/camera_types.h"
#include "host/util/image_io.h"

namespace lorgnette::fit {

constexpr double kIrisDiameterMm = 11.7;
constexpr double kIrisDiameterSdMm = 0.5;

struct IrisEdgeOptions {
  // How far left and right of the centre guess to look, and how far up and down for rows: in units
  // of the expected iris radius (the caller's guess from the eye corners).
  double search_radii = 2.2, row_radii = 0.7;
  // An edge counts when the luminance outside it (sclera) exceeds the inside (iris) by this share of
  // the outside: a limbus is a strong step (brown or blue iris on white sclera: 50-90 %); eyelids,
  // lashes and a blurred render are not.
  double min_relative_step = 0.25;
  int min_rows = 4;              // rows with both edges found, for the circle fit
  double max_residual_px = 1.5;  // rows whose chord is further than this off the fitted circle are dropped
};

// The limbus in one image: a circle fitted to the left and right edges of the dark iris along the
// rows through it.
struct IrisEdges {
  bool found = false;
  std::string why;  // when not found
  Eigen::Vector2d centre_px = Eigen::Vector2d::Zero();
  double diameter_px = 0.0;
  double relative_step = 0.0;  // median (outside - inside) / outside over the edges used
  int rows = 0;                // rows whose edges were used
};

// Finds the iris near `centre_guess` (pixels) whose radius is about `radius_guess_px` (within a
// factor of 2): per row, the darkest stretch and the strongest dark-to-light steps either side of it
// (sub-pixel), then a least-squares circle through those edge points (rows cut by an eyelid still lie
// on it). The image is linear RGB(A); luminance is Rec. 709.
IrisEdges find_iris_edges(const Image& image, const Eigen::Vector2d& centre_guess, double radius_guess_px,
                          const IrisEdgeOptions& options = {});

// One eye in one view: the limbus diameter converted to scene units with the view's camera.
struct IrisMeasurement {
  int eye = 0;  // +1 the wearer's left, -1 the right
  bool closed = false;
  IrisEdges edges;
  double diameter_units = 0.0;  // edges.diameter_px * depth / fx: the eye seen square-on
  // The limbus' centre (the pupil's, within a fraction of a millimetre) on the eye's surface, scene
  // units: where the ray through edges.centre_px meets the head; found with the edges.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
};

// Scene units across `diameter_px` pixels of `cam` at the depth of `point` (a pinhole: width = px *
// depth / fx). Throws when the point is behind the camera.
double pixels_to_units(const Camera& cam, const Eigen::Vector3d& point, double diameter_px);

struct IrisScaleOptions {
  double max_eye_disagreement = 0.08;  // |left - right| / mean: the two irises are the same size
  // Refused when it differs from the mean face's scale by more than this share: the mean face is
  // good to about 10 %, so a larger gap means the edges were something else (lashes, a reflection).
  double max_gap_to_mean_face = 0.25;
  int min_per_eye = 1;
};

struct IrisScale {
  bool ok = false;
  std::string why;  // why it was refused, or a summary when ok
  double mm_per_unit = 0.0, mm_per_unit_uncertainty = 0.0;
  double diameter_units = 0.0;  // mean over the measurements used
  int measurements = 0;
};

// mm per unit = 11.7 / the mean diameter; its 1-sigma uncertainty combines the population SD
// (0.5 / 11.7) with the measurements' spread (standard error of their mean).
IrisScale iris_scale(const std::vector<IrisMeasurement>& measurements, double mean_face_mm_per_unit,
                     const IrisScaleOptions& options = {});

}  // namespace lorgnette::fit
