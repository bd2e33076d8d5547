// The ear search's line finder (docs/fit.md, "The ear search"): the crease in each depth's profile
// of the ray field (ear_rays.h), the creases traced across depths into lines along the ear's root,
// the lines ordered, and each line's rest, where a temple arm lowered onto the ear comes to rest.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "fit/ear_rays.h"

namespace lorgnette::fit {

// The crease between skull and ear in one depth's profile (heights along d_eye, inside to outside):
// the heights fall steeply down the skull's side, then turn flatter onto the ear's top, which stands
// out from the head. The crease is where the slope (over `bend_span_mm` either side) turns most, by at
// least `min_bend_deg` (not bounded above: where the skull bulges over the ear the rays drop off it
// onto the ear at ~90 deg). Hair and the inside of a NeRF's head bend too, on flatter ground, so the
// inside must fall at least as steeply as `max_inner_slope_deg`; the outside must be an ear's top,
// not an edge nor a wall (`outer_slope_deg`, + = rising); the crease lies in a height band above the
// eye corner where ears lie (`lowest_mm`..`highest_mm`).
struct EarCreaseOptions {
  double min_bend_deg = 20.0, bend_span_mm = 3.0;
  double max_inner_slope_deg = -45.0;
  double outer_slope_deg[2] = {-60.0, 30.0};
  double lowest_mm = -5.0, highest_mm = 30.0;
};

// Lines of creases and their rests.
// - An ear's root is a smooth line: creases at neighbouring depths continue a line only within
//   `max_step_mm` (along d_eye and along d_up); hair gives creases that jump. A line needs
//   `min_slices` consecutive depths.
// - A line shorter than `short_line_slices` above the highest line at least that long follows it:
//   a temple slides under hair's edge onto the ear's root.
// - The rest's height is the mean of the creases whose height (a median over three depths: a NeRF's
//   heights scatter by a millimetre or two) lies within `plateau_mm` of the line's highest: the top
//   of the root is a plateau a few depths long.
// - Its width is the mean over the root's top of the creases' widths, each weighted by how far its
//   (median) height lies above the highest minus `depth_window_mm` (0: the plateau's mean), so that
//   the whole top counts, not a few scattered depths of it.
// - Its depth is `rest_behind_front_mm` behind the line's front end (no further back than its back
//   end), where the root leaves the head: a NeRF fills the gap between the ear's back and the skull,
//   so its lines run further back than the exact mesh's, while their front ends agree.
struct EarLineOptions {
  double max_step_mm = 5.0;
  int min_slices = 3;
  int short_line_slices = 5;
  double plateau_mm = 1.5;
  double depth_window_mm = 4.0;
  double rest_behind_front_mm = 9.0;
};

// One depth's crease: where it lies (mm outwards from the temple, above the eye corner), how sharply
// the profile bends there, and the ear's top outside it: its height `span` samples out (`top_mm`), and
// (lateral, height) at each sample from there outwards while the profile keeps an ear top's slope
// (`outer_slope_deg` from one sample to the next), at most `span` samples further (`top`). The top's
// width is where its colour is read: hair hanging over the root covers the top's inner edge, while an
// ear under hair is dark across it.
struct EarCrease {
  bool found = false;
  double lateral_mm = 0.0, height_mm = 0.0, bend_deg = 0.0;
  double top_mm = 0.0;
  std::vector<Eigen::Vector2d> top;
};

// The crease in one profile, `span` samples either side (NaN heights are misses: all three must hit).
EarCrease find_crease(const std::vector<double>& heights, const std::vector<double>& laterals, int span,
                      const EarCreaseOptions& o);

// A run of consecutive depths whose creases continue each other: creases[start .. start + len), each
// one's height smoothed (the median of it and its two nearest neighbours in the run), and the
// highest smoothed height.
struct EarCreaseLine {
  int start = 0, len = 0;
  std::vector<double> smooth;
  double top = 0.0;
};

// Every run of found creases (of any length), in depth order.
std::vector<EarCreaseLine> trace_crease_lines(const std::vector<EarCrease>& creases, double max_step_mm);

// Highest first; then the first line at least `short_line_slices` long moved to the front.
void order_crease_lines(std::vector<EarCreaseLine>& lines, int short_line_slices);

// One side's result: a line of creases and its rest, or why the side has none.
struct EarRootSide {
  bool found = false;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // the rest (scene units)
  double height_mm = 0.0;                           // the rest above the side's outer eye corner (along d_up)
  double depth_mm = 0.0;    // along d_fwd from the temple landmark (negative: behind it)
  double lateral_mm = 0.0;  // and outwards from it along the side's d_eye
  bool vetoed = false;      // found, then refused by the caller's veto (`why` says why)
  int higher_vetoed = 0;    // higher lines of creases on this side that the veto refused
  int passed_over = 0;      // higher lines it accepted too, passed over for a pair that agrees in depth
  double bend_deg = 0.0;    // how sharply the profile turns there
  int slices = 0;  // consecutive depths holding the chosen line of creases (or the longest, when too short)
  double back_mm = 0.0, front_mm = 0.0;  // the line's first and last depth (along d_fwd from the temple)
  int plateau = 0;                       // of them, those averaged into the rest's height
  // Per plateau depth, the ear's top outside its crease across the top's width (scene; EarCrease::top,
  // or the one point `bend_span_mm` out where a crease has none), for the caller's look at its colour
  // (hair is not an ear).
  std::vector<std::vector<Eigen::Vector3d>> ear_top;
  std::string why;  // when not found: what the window showed
};

// The rest on `line` (of `creases` at `depths`), found. `bend_span_mm`: how far outside each crease
// its ear top lies.
EarRootSide rest_of_line(const EarCreaseLine& line, const std::vector<EarCrease>& creases,
                         const std::vector<double>& depths, const EarLineOptions& o,
                         const EarSideFrame& frame, double bend_span_mm);

}  // namespace lorgnette::fit
