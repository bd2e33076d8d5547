// Finding a held ID-1 card (ISO/IEC 7810: 85.60 x 53.98 mm) in one photo, whatever is printed on it:
// a region brighter (or darker) than its surroundings whose outline is a convex quadrilateral with
// the card's proportions under perspective. Candidates come from local thresholding of both
// polarities and at a ladder of grey levels (the card's outer contour; its printing only makes holes),
// four sides of the convex hull (a finger biting into an edge or over a corner leaves them), and each side is
// then re-measured as a straight edge: the strongest step along the side's normal at many places, a line
// fitted to them with the places under a finger rejected as outliers. Corners are the lines'
// intersections, so a covered corner is still found where its edges meet.
#pragma once
#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <vector>

namespace lorgnette::capture {

constexpr double kCardWidthMm = 85.60, kCardHeightMm = 53.98;

struct CardQuad {
  // Continuous pixel coordinates (pixel centres at i + 0.5), clockwise in the image from the corner
  // nearest the image's top-left.
  std::array<Eigen::Vector2d, 4> corners;
  double edge_support = 0.0;  // share of the places along the four sides where the edge was found
  double contrast = 0.0;      // mean grey step across the sides (0..255)
  double score() const { return edge_support * contrast; }
};

struct CardDetectOptions {
  double min_area_fraction = 0.002;            // of the image: smaller quads are too few pixels to measure
  double max_area_fraction = 0.25;             // larger ones are walls and doors, not a card at a face
  double min_aspect = 1.15, max_aspect = 2.2;  // long over short sides: 1.586 seen up to ~40 deg off
  double min_edge_support = 0.4;               // a finger may hide up to 60 % of the places along a side
  int max_candidates = 4;                      // the best by score
};

// Candidates, best first (empty when none). `image`: 8-bit grey or BGR.
std::vector<CardQuad> detect_card_quads(const cv::Mat& image, const CardDetectOptions& options = {});

}  // namespace lorgnette::capture
