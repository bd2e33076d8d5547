// Soft studio lighting for the glasses, chosen to sit with a NeRF head captured in soft light: a
// hemisphere ambient term (sky above, ground below) plus one key light with an optional soft
// shadow. Directions are in the glasses' canonical frame (x wearer's left, +y up, +z forward), so
// the lighting moves with the head the frame sits on, as the head's baked lighting does.
#pragma once
#include <Eigen/Core>

namespace lorgnette::mesh {

struct Lighting {
  Eigen::Vector3f sky{0.50f, 0.50f, 0.52f};             // ambient radiance from above (linear RGB)
  Eigen::Vector3f ground{0.22f, 0.20f, 0.19f};          // ambient radiance from below
  Eigen::Vector3f key_direction{-0.35f, 0.55f, 0.76f};  // towards the light (normalised on use)
  Eigen::Vector3f key_irradiance{1.6f, 1.55f, 1.5f};    // at normal incidence
  float key_shadow = 0.6f;  // 0 = no shadows, 1 = hard shadows (soft light: partial)
};

// Hemisphere environment radiance in canonical direction d (unit): a smooth sky-ground blend.
inline Eigen::Vector3f environment(const Lighting& l, const Eigen::Vector3f& d_canonical) {
  float t = 0.5f + 0.5f * d_canonical.y();
  return l.ground + t * (l.sky - l.ground);
}

}  // namespace lorgnette::mesh
