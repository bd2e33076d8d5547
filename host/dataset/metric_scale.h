// A dataset's metric scale, scale.json beside transforms.json: millimetres per dataset unit (the
// coordinates of transforms.json) measured by `capture` from an object of known size, with its
// uncertainty (one standard error) and the source, e.g.
//   {"source": "card", "mm_per_unit": 212.4, "mm_per_unit_uncertainty": 0.6, "frames": 14}
// `train` carries it into the model's metadata (host/nerf/snapshot.h) converted to scene units.
#pragma once
#include <optional>
#include <string>

namespace lorgnette::dataset {

inline constexpr const char* kScaleFile = "scale.json";

struct MetricScale {
  std::string source;        // "card"
  double mm_per_unit = 0.0;  // > 0
  double uncertainty = 0.0;  // >= 0, millimetres per unit
  int frames = 0;            // frames the measurement used
};

// Throws std::runtime_error (naming the value) unless mm_per_unit > 0 and uncertainty >= 0, finite.
void check_metric_scale(const MetricScale& s, const std::string& where);

void write_scale_json(const std::string& dataset_dir, const MetricScale& s);

// Absent file: nullopt. Unreadable or malformed: std::runtime_error saying what is wrong and that
// deleting the file makes the scale unknown.
std::optional<MetricScale> read_scale_json(const std::string& dataset_dir);

}  // namespace lorgnette::dataset
