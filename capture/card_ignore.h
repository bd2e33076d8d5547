// Where training must not look in the frames that show the held card: the card itself and the
// fingers on it are in some frames only, so no static scene explains them, and a NeRF trained on them
// bakes a ghost of the card into the head. Per frame, the card's quadrilateral grown by a margin in
// the card's own plane (millimetres of the card, so it shrinks with distance as the fingers do), and
// a strip along each finger that crosses its edges (capture/card_fingers.h), written as ignore regions
// (host/dataset/ignore_regions.h) that training leaves out. Frames: those the card was measured in (their own
// corners, mapped through the frame's card homography); the frames between the first and the last of them
// (the triangulated card projected: a card held to the head for part of a sweep stays there, and the detector
// misses some of those frames to motion blur, a finger over a corner or an oblique view); and frames before
// the first or after the last whose pixels where the card projects look like the measured card's face
// (normalised cross-correlation with their median): at the ends of the card's part of the sweep the card is
// seen obliquely and the detector misses it, yet its picture is there to be learnt. Other frames get no
// region, so the head behind the card is learnt from the frames without it.
#pragma once
#include <string>
#include <vector>

#include "capture/card_fingers.h"
#include "capture/card_scale.h"
#include "host/dataset/ignore_regions.h"

namespace lorgnette::capture {

struct CardIgnoreOptions {
  // Around every edge, in the card's millimetres: fingers hold a card at its edges, and an adult
  // finger is 15-20 mm wide, so a fingertip on an edge reaches up to its width beyond it; 20 mm covers
  // it and the detected corners' error (a few px, ~1-3 mm at a face). A finger's length beyond the
  // card is not covered by the margin (it may come from any side; a margin that large would take
  // the eyes): `fingers` finds the fingers that cross an edge and adds a strip along each.
  double margin_mm = 20.0;
  CardFingerOptions fingers;
  // A frame outside the measured ones shows the card when its patch correlates with the card's face
  // at least this much (-1..1). Skin, hair and a wall correlate near 0 with a printed card (-0.19 to
  // 0.17 on the 16 frames without it of synth's room 1 card capture, seed 3), the card seen obliquely
  // or under a finger well above it (0.64 to 0.98 on the 4 frames the detector missed): midway.
  double min_likeness = 0.5;
};

// views: the dataset's frames in capture order (sorted by file path, as the dataset loads them);
// greys: each view's image in grey, at any size (scaled from its camera's), or none (then frames
// outside the measured ones are not searched); card: a found card. Frames without a region are not
// listed.
std::vector<dataset::FrameIgnore> card_ignore_regions(const std::vector<CardView>& views,
                                                      const std::vector<cv::Mat>& greys,
                                                      const CardScale& card,
                                                      const CardIgnoreOptions& options = {});

}  // namespace lorgnette::capture
