// The simplified Disney BRDF (Burley 2012, "Physically-Based Shading at Disney", section 5.3):
// base colour, metallic, roughness, specular. Diffuse: Burley's retro-reflective lobe
// f_d = base/pi * (1 + (F_D90 - 1)(1 - cos_l)^5)(1 + (F_D90 - 1)(1 - cos_v)^5) * (1 - metallic),
// with the energy renormalisation of Lagarde & de Rousiers 2014 (Frostbite: F_D90 = bias +
// 2 roughness cos_d^2, bias = 0.5 roughness, factor lerp(1, 1/1.51, roughness)), because Burley's
// original lobe reflects up to ~7 % more than it receives at roughness 1; and a reciprocal coupling
// (1 - F(cos_l))(1 - F(cos_v)) so that light reflected by the specular layer at grazing angles is
// not also diffused (the white furnace test checks albedo <= 1). Specular: microfacet GGX
// (alpha = roughness^2) with the usual 1/(4 cos_l cos_v) normalisation, Schlick Fresnel from
// F0 = mix(0.08 specular, base, metallic) and height-correlated Smith masking (Heitz 2014). Written once for
// host code; the surface pass runs on the CPU (Embree), so no OpenCL copy exists. All vectors are unit length
// in one frame; cos values below 0 mean "below the surface" and return 0.
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace lorgnette::mesh {

struct BrdfParams {
  Eigen::Vector3f base_color{0.8f, 0.8f, 0.8f};
  float metallic = 0.0f;
  float roughness = 0.5f;
  float specular = 0.5f;
};

constexpr float kPi = 3.14159265358979323846f;

inline float schlick_weight(float cos_theta) {
  float m = std::clamp(1.0f - cos_theta, 0.0f, 1.0f);
  float m2 = m * m;
  return m2 * m2 * m;
}

// Fresnel reflectance of a dielectric interface (unpolarised, exact), cos_i > 0 on the incident side.
inline float fresnel_dielectric(float cos_i, float eta) {
  cos_i = std::clamp(cos_i, 0.0f, 1.0f);
  float sin_t2 = (1.0f - cos_i * cos_i) / (eta * eta);
  if (sin_t2 >= 1.0f) return 1.0f;
  float cos_t = std::sqrt(1.0f - sin_t2);
  float rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  float rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5f * (rs * rs + rp * rp);
}

// GGX / Trowbridge-Reitz normal distribution, alpha = roughness^2 (clamped away from a delta).
inline float ggx_d(float cos_h, float alpha) {
  float a2 = alpha * alpha;
  float d = cos_h * cos_h * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * d * d);
}

// Height-correlated Smith G2 for GGX divided by (4 cos_l cos_v) ("visibility" V).
inline float ggx_visibility(float cos_l, float cos_v, float alpha) {
  float a2 = alpha * alpha;
  float gv = cos_l * std::sqrt(cos_v * cos_v * (1.0f - a2) + a2);
  float gl = cos_v * std::sqrt(cos_l * cos_l * (1.0f - a2) + a2);
  return 0.5f / (gv + gl);
}

inline float disney_alpha(float roughness) {
  float r = std::clamp(roughness, 0.02f, 1.0f);  // 0.02: keeps D finite for mirror-like inputs
  return r * r;
}

// f(l, v) for normal n: reflected radiance per unit irradiance (1/sr), RGB. Reciprocal in l and v.
inline Eigen::Vector3f disney_brdf(const BrdfParams& p, const Eigen::Vector3f& n, const Eigen::Vector3f& l,
                                   const Eigen::Vector3f& v) {
  float cos_l = n.dot(l), cos_v = n.dot(v);
  if (cos_l <= 0.0f || cos_v <= 0.0f) return Eigen::Vector3f::Zero();
  Eigen::Vector3f h = (l + v).normalized();
  float cos_h = std::max(n.dot(h), 0.0f);
  float cos_d = std::clamp(l.dot(h), 0.0f, 1.0f);
  float fl = schlick_weight(cos_l), fv = schlick_weight(cos_v);
  float energy_bias = 0.5f * p.roughness, energy_factor = 1.0f + p.roughness * (1.0f / 1.51f - 1.0f);
  float fd90 = energy_bias + 2.0f * cos_d * cos_d * p.roughness;
  float fd = (1.0f + (fd90 - 1.0f) * fl) * (1.0f + (fd90 - 1.0f) * fv) * energy_factor;
  Eigen::Vector3f f0 =
      (1.0f - p.metallic) * Eigen::Vector3f::Constant(0.08f * p.specular) + p.metallic * p.base_color;
  float f0d = 0.08f * p.specular;  // the dielectric layer the diffuse light passes twice
  float coupling = (1.0f - (f0d + (1.0f - f0d) * fl)) * (1.0f - (f0d + (1.0f - f0d) * fv));
  Eigen::Vector3f diffuse = p.base_color * (fd * coupling / kPi * (1.0f - p.metallic));
  float fh = schlick_weight(cos_d);
  Eigen::Vector3f fresnel = f0 + (Eigen::Vector3f::Ones() - f0) * fh;
  float alpha = disney_alpha(p.roughness);
  Eigen::Vector3f spec = fresnel * (ggx_d(cos_h, alpha) * ggx_visibility(cos_l, cos_v, alpha));
  return diffuse + spec;
}

// Lambertian limit of the model: f = base/pi. At roughness 0 and specular 0 with light and view
// along the normal all Fresnel weights vanish and the Disney BRDF equals it exactly.
inline Eigen::Vector3f lambert_brdf(const Eigen::Vector3f& base) { return base / kPi; }

}  // namespace lorgnette::mesh
