// The card step of `capture` on a posed dataset (transforms.json and its images): every frame
// searched for a held ID-1 card (capture/card_detect.h), the scale measured from the frames that
// agree (capture/card_scale.h), and scale.json (host/dataset/metric_scale.h) written when it was;
// a scale.json left by an earlier measurement is removed when this one finds none, so the dataset
// never claims a scale its frames do not give. Also runs on synth outputs and other posed datasets.
#pragma once
#include <string>

#include "capture/card_scale.h"

namespace lorgnette::capture {

struct DatasetCardResult {
  CardScale scale;
  double seconds = 0.0;        // detection and measurement together
  bool scale_written = false;  // scale.json holds this measurement
};

// Throws std::runtime_error when the dataset cannot be read; a card not found is a result, not an error.
DatasetCardResult measure_dataset_card(const std::string& dataset_dir, const CardDetectOptions& detect = {},
                                       const CardScaleOptions& scale = {});

}  // namespace lorgnette::capture
