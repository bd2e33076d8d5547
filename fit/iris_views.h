// The irises measured on a ViewSource (iris.h): for each eye, narrow views aimed at the eye's centre
// (the mean of its six dlib landmarks, triangulated) from in front of that eye along the face's
// forward direction and a few degrees to either side, rendered at a resolution where the iris is
// tens of pixels across; the limbus found (find_iris_edges) and converted to scene units at the eye's
// depth. Views from in front of each eye, not from the cap's cameras: an iris faces forward, and a
// view from the other side of the face sees it foreshortened by more than the view's angle to the
// face (the face curves away there), which no correction by that angle undoes. An eye whose lids
// nearly meet is marked closed and not measured.
#pragma once
#include <array>
#include <vector>

#include "fit/iris.h"
#include "fit/view_source.h"

namespace lorgnette::fit {

// The six landmarks of one eye in dlib order: a corner, two upper-lid points, the other corner, two
// lower-lid points (36-41 for the right eye, 42-47 for the left), scene units.
using EyeContour = std::array<Eigen::Vector3d, 6>;

struct IrisViewOptions {
  int width = 256, height = 128;  // each eye's view: the iris ~40 px across at the span below
  double span_eye_widths = 2.0;   // the view's width in eye widths (corner to corner)
  // The iris is about 0.39 eye widths across (11.7 of ~30 mm); the edge search allows 2x either way.
  double iris_per_eye_width = 0.39;
  // Lid opening / eye width below which the eye counts as closed: an open adult eye shows ~0.25-0.35
  // (the eye aspect ratio of blink detectors; below ~0.2 the lids cover the limbus' sides).
  double closed_ratio = 0.18;
  // The views' directions about the head's up, from the face's forward (each eye's own views): a few
  // degrees apart, so the NeRF's view-dependent errors average; the cos() foreshortening is divided out.
  std::vector<double> yaw_deg = {-6.0, 0.0, 6.0};
  IrisEdgeOptions edges;
};

// Lid opening over eye width ((|p1 - p5| + |p2 - p4|) / 2|p0 - p3|).
double eye_opening_ratio(const EyeContour& eye);

// Measures both eyes from `distance` (scene units; the capture's own, so the NeRF is seen as it was
// trained) in front of each, at each of options.yaw_deg. `d_up` is the head's up (the views' rows run
// along the eyes' line) and `d_fwd` its forward (unit vectors).
std::vector<IrisMeasurement> measure_irises(ViewSource& source, const EyeContour& left,
                                            const EyeContour& right, const Eigen::Vector3d& d_up,
                                            const Eigen::Vector3d& d_fwd, double distance,
                                            const IrisViewOptions& options = {});

}  // namespace lorgnette::fit
