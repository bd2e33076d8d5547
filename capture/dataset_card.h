// The card step of `capture` on a posed dataset (transforms.json and its images): every frame
// searched for a held ID-1 card (capture/card_detect.h), the scale measured from the frames that
// agree (capture/card_scale.h), and scale.json (host/dataset/metric_scale.h) written when it was,
// with ignore_regions.json (the card and its fingers in the frames that show it, capture/card_ignore.h)
// for training to leave out; files left by an earlier measurement are removed when this one finds
// no card, so the dataset never claims a scale or hides pixels its frames do not call for. Also runs on synth
// outputs and other posed datasets.
#pragma once
#include <string>

#include "capture/card_ignore.h"
#include "capture/card_scale.h"

namespace lorgnette::capture {

struct DatasetCardResult {
  CardScale scale;
  double seconds = 0.0;        // detection and measurement together
  bool scale_written = false;  // scale.json holds this measurement
  int ignore_frames = 0;       // frames given an ignore region (ignore_regions.json, when > 0)
};

// Throws std::runtime_error when the dataset cannot be read; a card not found is a result, not an error.
DatasetCardResult measure_dataset_card(const std::string& dataset_dir, const CardDetectOptions& detect = {},
                                       const CardScaleOptions& scale = {},
                                       const CardIgnoreOptions& ignore = {});

}  // namespace lorgnette::capture
