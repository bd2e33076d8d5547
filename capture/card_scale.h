// Millimetres per dataset unit from an ID-1 card seen in posed frames: the card's candidate quads
// (capture/card_detect.h) in each frame, one card found consistent across frames (a hypothesis from
// two frames, kept by the frames whose quads it reprojects onto), its corners triangulated with the
// known poses, and the scale from its four edges (85.60 and 53.98 mm) over their length in dataset
// units. The uncertainty is the jackknife standard error over the frames (each left out in turn), so
// it grows with the spread of the frames' measurements and shrinks with their number.
// Refused (found = false, `message` says why and what to film differently) when the card is seen in
// too few frames, only obliquely, or its edges disagree (bent, or not a card): the caller falls back.
#pragma once
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "capture/card_detect.h"
#include "common/camera_types.h"

namespace lorgnette::capture {

struct CardView {
  std::string name;  // the frame's image, for messages
  Camera camera;     // pose in the dataset frame
  std::vector<CardQuad> candidates;
};

struct CardScaleOptions {
  int min_frames = 4;                // frames that must agree on the card
  double max_obliquity_deg = 65.0;   // frames seeing the card's face more obliquely are left out
  double max_edge_mismatch = 0.03;   // opposite edges' lengths may differ by this share (bend, shear)
  double max_aspect_error = 0.03;    // long over short edges against 85.60 / 53.98
  double max_diagonal_error = 0.03;  // diagonals against a rectangle's
  double reprojection_px = 0.02;     // a frame agrees when its corners lie within this share of the
                                     // image diagonal (plus 1.5 px) of the card's reprojection
  double focus_reach = 0.5;          // the card lies within this share of the cameras' distance
                                     // from the point they aim at (it is held at the face)
};

struct CardScale {
  bool found = false;
  std::string message;  // what was measured, or why no scale (and what to film differently)
  double mm_per_unit = 0.0, uncertainty = 0.0;  // per dataset unit; uncertainty: one standard error
  int frames = 0;                               // frames whose corners made the measurement
  std::array<Eigen::Vector3d, 4> corners{};     // dataset frame, in the order of the first frame's quad
  std::array<double, 4> edges_mm{};             // the four edges at the measured scale
  std::vector<std::string> frame_names;
  // Per frame_names entry: the card's corners seen in that frame, in the order of `corners`.
  std::vector<std::array<Eigen::Vector2d, 4>> frame_corners;
};

CardScale measure_card_scale(const std::vector<CardView>& views, const CardScaleOptions& options = {});

// The least-squares point nearest to the rays (origins, unit directions); needs two rays that are not
// parallel.
Eigen::Vector3d nearest_point_to_rays(const std::vector<Eigen::Vector3d>& origins,
                                      const std::vector<Eigen::Vector3d>& dirs);

}  // namespace lorgnette::capture
