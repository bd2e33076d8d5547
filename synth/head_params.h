// Parameters of the procedural human head: overall proportions, the facial layout and the colours
// of the painted texture, all in millimetres / linear RGB. `random_head_params(seed)` draws a
// plausible adult head (uniform within anthropometric ranges) so every seed is a different subject
// with exactly known geometry. JSON round-trip for ground_truth.json.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <nlohmann/json_fwd.hpp>

namespace lorgnette::synth {

struct HeadParams {
  uint64_t seed = 0;
  float head_width = 150.0f;      // cranium breadth (ear roots excluded)
  float head_depth = 196.0f;      // glabella to back of head
  float crown_height = 122.0f;    // eye level to the top of the head
  float face_length = 114.0f;     // eye level to the chin (menton)
  float eye_distance = 64.0f;     // interpupillary distance (eye centres)
  float eye_width = 28.0f;        // palpebral fissure (corner to corner)
  float eye_opening = 8.5f;       // upper lid peak to lower lid trough
  float nose_length = 34.0f;      // bridge (nasion, landmark 27) to the tip (30)
  float nose_protrusion = 30.0f;  // tip in front of the inner eye corners
  float nose_width = 32.0f;       // alar width
  float mouth_width = 56.0f;      // corner to corner
  float lip_thickness = 1.0f;     // scale of the lip heights
  float brow_height = 21.0f;      // brow arch peak above eye level
  float ear_length = 60.0f;
  // Horizontal visible iris diameter (adults: about 11.7 mm, spread about 0.5 mm). It is painted at
  // exactly this size, so it is the ground truth of an iris-based scale.
  float iris_diameter = 11.76f;
  Eigen::Vector3f skin{0.62f, 0.38f, 0.27f};  // linear RGB albedo
  Eigen::Vector3f hair{0.035f, 0.022f, 0.015f};
  Eigen::Vector3f iris{0.10f, 0.06f, 0.03f};
  Eigen::Vector3f lips{0.42f, 0.14f, 0.12f};
};

// Deterministic plausible head for a seed (seed 0 = the defaults above).
HeadParams random_head_params(uint64_t seed);

// `p` with every length scaled by `factor` (0.85..1.15, else std::runtime_error) except the iris
// diameter, which varies little between adults whatever their head size: the ground truth of head
// sizes around the seeded ones (a metric scale must tell a small head from a far one).
HeadParams scale_head(const HeadParams& p, float factor);

// Throws std::runtime_error naming the parameter when a value is outside its plausible range.
void validate(const HeadParams& p);

void to_json(nlohmann::json& j, const HeadParams& p);

}  // namespace lorgnette::synth
