// Fingers that hold a card, found where they cross its edges: along each edge of the card in a frame,
// the grey step from just inside the card to just outside it (the card's outline, which the
// detector found by its contrast) vanishes where a finger lies over the edge, since the finger is on
// both sides of it, and the inside there is not the card's (a pale wall beside a pale card also
// takes the step away, but the inside is still the card). Each stretch of an edge without its step, as wide
// as a finger or wider, gives a strip from that stretch outward across the face, as long as a finger, in the
// card's plane: the part of the finger beyond the card that a margin around the card does not reach (a finger
// from below crosses the brows and the nose). The rest of the hand is not followed.
#pragma once
#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <utility>
#include <vector>

#include "host/dataset/ignore_regions.h"

namespace lorgnette::capture {

struct CardFingerOptions {
  // An edge place is covered when its step is below this share of the median step over the card's
  // four edges in that frame (a finger on both sides of the edge leaves a step near 0, a printed card
  // against skin, hair or a wall keeps most of its contrast) and its inside differs from the median
  // inside by more than the same share.
  double covered_step = 0.35;
  double min_median_step = 8.0;    // grey levels: below it the outline is too faint to judge
  double min_stretch_mm = 8.0;     // covered stretches shorter than this are printing, not a finger
  double max_covered = 0.6;        // an edge covered more than this is faint, not held (no strips)
  double finger_length_mm = 70.0;  // an adult index finger is 70-80 mm from its tip to the knuckle
  double side_mm = 10.0;           // the strip's widening on each side (a leaning finger, blur)
};

// Strips (image pixels, continuous coordinates) for the fingers crossing the card's edges in one frame.
// grey: the frame at any size (scaled from width x height); corners: the card's corners in the
// frame's pixels, in card order; sides: the card's millimetres along corner 0 -> 1 and 1 -> 2.
std::vector<dataset::IgnorePolygon> finger_strips(const cv::Mat& grey, int width, int height,
                                                  const std::array<Eigen::Vector2d, 4>& corners,
                                                  std::pair<double, double> sides,
                                                  const CardFingerOptions& options = {});

}  // namespace lorgnette::capture
