// Seeded head parameters; see head_params.h. Ranges are adult anthropometric ranges (roughly the
// 5th-95th percentiles of head breadth, interpupillary distance, nose and mouth sizes), with skin,
// hair and iris colours drawn from a small palette so every seed still reads as a face.
#include "synth/head_params.h"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <random>
#include <stdexcept>

namespace lorgnette::synth {
namespace {

Eigen::Vector3f srgb(float r, float g, float b) {
  auto lin = [](float c) {
    c /= 255.0f;
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
  };
  return {lin(r), lin(g), lin(b)};
}

void check(const char* name, float v, float lo, float hi) {
  if (!(v >= lo && v <= hi))
    throw std::runtime_error(
        fmt::format("procedural head: {} = {} mm is outside the plausible range [{}, {}]", name, v, lo, hi));
}

}  // namespace

HeadParams random_head_params(uint64_t seed) {
  HeadParams p;
  p.seed = seed;
  if (seed == 0) return p;
  std::mt19937_64 rng(seed);
  auto uni = [&](float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); };
  p.head_width = uni(140.0f, 160.0f);
  p.head_depth = uni(185.0f, 205.0f);
  p.crown_height = uni(115.0f, 128.0f);
  p.face_length = uni(106.0f, 120.0f);
  p.eye_distance = uni(59.0f, 69.0f);
  p.eye_width = uni(26.5f, 30.0f);
  p.eye_opening = uni(8.0f, 9.5f);
  p.nose_length = uni(31.0f, 37.0f);
  p.nose_protrusion = uni(26.0f, 33.0f);
  p.nose_width = uni(29.0f, 36.0f);
  p.mouth_width = uni(50.0f, 60.0f);
  p.lip_thickness = uni(0.85f, 1.15f);
  p.brow_height = uni(19.0f, 23.0f);
  p.ear_length = uni(55.0f, 66.0f);
  p.iris_diameter = 0.42f * p.eye_width;  // no draw: the seeds' other parameters stay as they were
  const Eigen::Vector3f skins[] = {srgb(236, 188, 160), srgb(224, 172, 140), srgb(198, 144, 110),
                                   srgb(170, 120, 90), srgb(130, 90, 66)};
  const Eigen::Vector3f hairs[] = {srgb(40, 30, 25), srgb(70, 48, 32), srgb(25, 22, 20), srgb(110, 80, 50)};
  const Eigen::Vector3f irises[] = {srgb(90, 60, 35), srgb(60, 90, 120), srgb(80, 100, 70), srgb(55, 38, 25)};
  p.skin = skins[rng() % 5];
  p.hair = hairs[rng() % 4];
  p.iris = irises[rng() % 4];
  p.lips = p.skin.cwiseProduct(Eigen::Vector3f(0.72f, 0.42f, 0.45f));
  return p;
}

HeadParams scale_head(const HeadParams& p, float factor) {
  if (!(factor >= 0.85f && factor <= 1.15f))
    throw std::runtime_error(fmt::format("head scale {} is outside 0.85..1.15", factor));
  HeadParams s = p;
  for (float* v : {&s.head_width, &s.head_depth, &s.crown_height, &s.face_length, &s.eye_distance,
                   &s.eye_width, &s.eye_opening, &s.nose_length, &s.nose_protrusion, &s.nose_width,
                   &s.mouth_width, &s.brow_height, &s.ear_length})
    *v *= factor;
  return s;
}

void validate(const HeadParams& p) {
  check("head_width", p.head_width, 115, 190);
  check("head_depth", p.head_depth, 150, 240);
  check("crown_height", p.crown_height, 95, 150);
  check("face_length", p.face_length, 88, 140);
  check("eye_distance", p.eye_distance, 48, 80);
  check("eye_width", p.eye_width, 22, 35);
  check("eye_opening", p.eye_opening, 6, 12);
  check("nose_length", p.nose_length, 25, 45);
  check("nose_protrusion", p.nose_protrusion, 18, 40);
  check("nose_width", p.nose_width, 24, 42);
  check("mouth_width", p.mouth_width, 40, 70);
  check("lip_thickness", p.lip_thickness, 0.6f, 1.5f);
  check("brow_height", p.brow_height, 15, 28);
  check("ear_length", p.ear_length, 45, 77);
  check("iris_diameter", p.iris_diameter, 9, 14);
}

void to_json(nlohmann::json& j, const HeadParams& p) {
  auto v3 = [](const Eigen::Vector3f& v) { return std::vector<float>{v.x(), v.y(), v.z()}; };
  j = {{"seed", p.seed},
       {"head_width", p.head_width},
       {"head_depth", p.head_depth},
       {"crown_height", p.crown_height},
       {"face_length", p.face_length},
       {"eye_distance", p.eye_distance},
       {"eye_width", p.eye_width},
       {"eye_opening", p.eye_opening},
       {"nose_length", p.nose_length},
       {"nose_protrusion", p.nose_protrusion},
       {"nose_width", p.nose_width},
       {"mouth_width", p.mouth_width},
       {"lip_thickness", p.lip_thickness},
       {"brow_height", p.brow_height},
       {"ear_length", p.ear_length},
       {"iris_diameter", p.iris_diameter},
       {"skin_linear", v3(p.skin)},
       {"hair_linear", v3(p.hair)},
       {"iris_linear", v3(p.iris)},
       {"lips_linear", v3(p.lips)}};
}

}  // namespace lorgnette::synth
