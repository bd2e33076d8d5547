// The irises measured on a ViewSource (iris.h): for each chosen camera position and each eye, a
// narrow view aimed at the eye's centre (the mean of its six dlib landmarks, triangulated), rendered
// at a resolution where the iris is tens of pixels across, its limbus found (find_iris_edges) and
// converted to scene units at the eye's depth. An eye whose lids nearly meet is marked closed and not
// measured.
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
  IrisEdgeOptions edges;
};

// Lid opening over eye width ((|p1 - p5| + |p2 - p4|) / 2|p0 - p3|).
double eye_opening_ratio(const EyeContour& eye);

// Measures both eyes from each of `camera_centres` (scene). `d_up` is the head's up (the views' rows
// run along the eyes' line) and `d_fwd` its forward: a view off the face's axis by a horizontal angle
// a sees the iris foreshortened by cos(a), which is divided out.
std::vector<IrisMeasurement> measure_irises(ViewSource& source,
                                            const std::vector<Eigen::Vector3d>& camera_centres,
                                            const EyeContour& left, const EyeContour& right,
                                            const Eigen::Vector3d& d_up, const Eigen::Vector3d& d_fwd,
                                            const IrisViewOptions& options = {});

}  // namespace lorgnette::fit
