// Painting the procedural head; see head_paint.h. Colours are linear RGB albedos; feature edges are
// softened over a fraction of a millimetre so the texture has no aliasing at any render size. The
// darkest features (lash line, pupils, nostrils, lip line, brows) are what a HOG face detector keys
// on, so they are painted with real-photo contrast against the skin.
#include "synth/head_paint.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "mesh/embree_scene.h"

namespace lorgnette::synth {
namespace {

using V2 = Eigen::Vector2f;
using V3 = Eigen::Vector3f;

float smoothstep(float e0, float e1, float x) {
  float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

V3 mix(const V3& a, const V3& b, float t) { return a + t * (b - a); }

float hash2(int x, int y) {
  uint32_t h = static_cast<uint32_t>(x) * 374761393u + static_cast<uint32_t>(y) * 668265263u;
  h = (h ^ (h >> 13)) * 1274126177u;
  return float(h ^ (h >> 16)) / 4294967295.0f;
}

// Smooth value noise in [0, 1].
float vnoise(float x, float y) {
  int ix = int(std::floor(x)), iy = int(std::floor(y));
  float fx = x - ix, fy = y - iy;
  fx = fx * fx * (3 - 2 * fx), fy = fy * fy * (3 - 2 * fy);
  float a = hash2(ix, iy), b = hash2(ix + 1, iy), c = hash2(ix, iy + 1), d = hash2(ix + 1, iy + 1);
  return (a + fx * (b - a)) + fy * ((c + fx * (d - c)) - (a + fx * (b - a)));
}

}  // namespace

HeadPainter::HeadPainter(const HeadParams& params, const FaceLayout& layout, const V3& ear_centre,
                         const V3& ear_radii, float face_front_z)
    : p_(params), f_(layout), ear_c_(ear_centre), ear_r_(ear_radii), front_z_(face_front_z) {}

float HeadPainter::hair_coverage(const V3& p) const {
  // Hairline height against the azimuth from the face (degrees): forehead, temple recess, over the
  // ears, down to the nape at the back.
  static constexpr float kAz[] = {0, 35, 55, 68, 82, 100, 118, 135, 180};
  const float ear_top = ear_c_.y() + ear_r_.y(), bh = p_.brow_height;
  const float hy_tab[] = {bh + 50, bh + 46, bh + 36, ear_top + 14, ear_top + 3, ear_top + 1, -25, -55, -62};
  float az = std::atan2(std::abs(p.x()), p.z()) * 180.0f / float(M_PI);
  int i = 0;
  while (i < 7 && az > kAz[i + 1]) ++i;
  float s = (az - kAz[i]) / (kAz[i + 1] - kAz[i]);
  float hy = hy_tab[i] + s * (hy_tab[i + 1] - hy_tab[i]) + 3.0f * (vnoise(az * 0.1f, 3.0f) - 0.5f);
  float cov = smoothstep(hy - 1.5f, hy + 1.5f, p.y());
  // The ears stay skin.
  V3 e = p - V3(std::copysign(ear_c_.x(), p.x()), ear_c_.y(), ear_c_.z());
  if (e.cwiseQuotient(ear_r_ + V3(6, 1, 2)).norm() < 1.0f && std::abs(p.x()) > ear_c_.x() - 8.0f) cov = 0.0f;
  return cov;
}

V3 HeadPainter::paint_brows(const V2& q, const V3& skin) const {
  V3 brow = mix(p_.hair, skin * 0.18f, 0.35f);
  V3 col = skin;
  for (const auto* curve : {&f_.brow_r, &f_.brow_l}) {
    const V2 lo = curve->front().cwiseMin(curve->back()) - V2(8, 12),
             hi = curve->front().cwiseMax(curve->back()) + V2(8, 12);
    if (q.x() < std::min(lo.x(), hi.x()) || q.x() > std::max(lo.x(), hi.x()) || q.y() < -5.0f) continue;
    // Thicker towards the inner end (curves run outer -> inner).
    float tx =
        std::clamp((q.x() - curve->front().x()) / (curve->back().x() - curve->front().x()), 0.0f, 1.0f);
    float thick = 3.2f + 3.0f * tx;
    float d = polyline_distance(*curve, q + V2(0, 0.4f * thick));
    float cov = 1.0f - smoothstep(0.5f * thick - 0.6f, 0.5f * thick + 0.6f, d);
    float strands = 0.75f + 0.5f * vnoise(q.x() * 1.7f, q.y() * 0.6f);
    col = mix(col, brow * strands, 0.92f * cov);
  }
  return col;
}

V3 HeadPainter::paint_eye(const EyeShape& eye, const V2& q, const V3& skin) const {
  float t = (q.x() - eye.outer.x()) / (eye.inner.x() - eye.outer.x());
  if (t < -0.3f || t > 1.3f || std::abs(q.y()) > 16.0f) return skin;
  float base = eye.outer.y() + std::clamp(t, 0.0f, 1.0f) * (eye.inner.y() - eye.outer.y());
  float b = lid_bump(t), up = base + eye.upper_height * b, lo = base - eye.lower_height * b;
  V3 col = skin;
  // Lid crease and the upper-lid shadow band above the lash line.
  float dy = q.y() - up;
  col *= 1.0f - 0.25f * std::exp(-std::pow((dy - 4.5f) / 1.6f, 2.0f)) * smoothstep(-0.2f, 0.1f, t) *
                    (1.0f - smoothstep(1.0f, 1.2f, t));
  bool inside = t > 0.0f && t < 1.0f && q.y() < up && q.y() > lo;
  if (inside) {
    V2 c = eye.centre();
    float r = (q - c).norm();
    V3 sclera = V3(0.50f, 0.47f, 0.44f) * (0.7f + 0.3f * b);
    V3 iris = p_.iris * (0.75f + 0.5f * (1.0f - r / f_.iris_radius));
    col = sclera;
    col = mix(col, iris * 0.5f, 1.0f - smoothstep(f_.iris_radius - 0.4f, f_.iris_radius + 0.2f, r));
    col = mix(col, iris, 1.0f - smoothstep(f_.iris_radius - 1.2f, f_.iris_radius - 0.6f, r));
    col = mix(col, V3(0.008f, 0.008f, 0.008f),
              1.0f - smoothstep(f_.pupil_radius - 0.3f, f_.pupil_radius + 0.3f, r));
    col *= 1.0f - 0.55f * std::exp(-(up - q.y()) / 1.3f);  // the upper lid's shadow on the eye
  }
  // Lash line along the upper lid (thicker towards the outer corner, running a little past it).
  float lash = (1.6f - 0.6f * std::clamp(t, 0.0f, 1.0f)) * smoothstep(-0.12f, 0.05f, t) *
               (1.0f - smoothstep(0.95f, 1.02f, t));
  float on_lash = smoothstep(-0.4f, 0.0f, dy) * (1.0f - smoothstep(lash - 0.3f, lash + 0.2f, dy)) *
                  smoothstep(0.0f, 0.3f, lash);
  col = mix(col, V3(0.012f, 0.01f, 0.01f), on_lash);
  float dl = lo - q.y();
  float lower =
      smoothstep(-0.3f, 0.0f, dl) * (1.0f - smoothstep(0.5f, 0.9f, dl)) * (t > 0 && t < 1 ? 1.0f : 0.0f);
  col = mix(col, col * 0.45f, lower);
  return col;
}

V3 HeadPainter::paint_nose(const V2& q, const V3& skin) const {
  V3 col = skin;
  const float nw = p_.nose_width;
  for (const V2& nc : {f_.nostril_r, f_.nostril_l}) {
    V2 d = q - nc;
    float e = std::sqrt(std::pow(d.x() / (0.12f * nw), 2.0f) + std::pow(d.y() / (0.07f * nw), 2.0f));
    col = mix(col, skin * 0.06f, 1.0f - smoothstep(0.8f, 1.2f, e));
  }
  // Shadow under the nose onto the upper lip.
  float base = f_.ibug[33].y();
  float w = 1.0f - smoothstep(0.3f * nw, 0.45f * nw, std::abs(q.x()));
  col *= 1.0f - 0.35f * w * std::exp(-std::pow((q.y() - base + 2.0f) / 2.5f, 2.0f));
  return col;
}

V3 HeadPainter::paint_mouth(const V2& q, const V3& skin) const {
  const float hw = f_.mouth_half_width;
  if (std::abs(q.x()) > hw + 4.0f || q.y() > f_.mouth_y + 16.0f || q.y() < f_.mouth_y - 20.0f) return skin;
  V3 col = skin;
  float line = f_.lip_line_y(q.x());
  float top = curve_y_at(f_.upper_lip_top, q.x()), bottom = curve_y_at(f_.lower_lip_bottom, q.x());
  if (!std::isnan(top) && !std::isnan(bottom)) {
    float upper = smoothstep(-0.3f, 0.3f, top - q.y()) * smoothstep(-0.1f, 0.1f, q.y() - line);
    float lower = smoothstep(-0.3f, 0.3f, q.y() - bottom) * smoothstep(-0.1f, 0.1f, line - q.y());
    col = mix(col, p_.lips * 0.85f, upper);
    col = mix(col, p_.lips, lower);
    // Shadow under the lower lip.
    col *= 1.0f - 0.25f * std::exp(-std::pow((q.y() - bottom + 3.0f) / 2.5f, 2.0f));
  }
  // Dark lip line, widening into the mouth corners.
  float u = std::abs(q.x()) / hw;
  float half = 0.55f + 0.5f * smoothstep(0.7f, 1.0f, u);
  float along = 1.0f - smoothstep(1.0f, 1.08f, u);
  float on_line = (1.0f - smoothstep(half - 0.3f, half + 0.3f, std::abs(q.y() - line))) * along;
  return mix(col, V3(0.02f, 0.008f, 0.008f), on_line);
}

V3 HeadPainter::paint_ear(const V3& p, const V3& skin) const {
  V3 e = p - V3(std::copysign(ear_c_.x(), p.x()), ear_c_.y(), ear_c_.z());
  float r = e.cwiseQuotient(ear_r_ + V3(4, 2, 2)).norm();
  if (r > 1.0f) return skin;
  V3 col = skin.cwiseProduct(V3(0.95f, 0.84f, 0.82f));
  // Concha: a darker hollow on the outer face of the ear.
  float inner = Eigen::Vector2f(e.y() / (0.55f * ear_r_.y()), e.z() / (0.55f * ear_r_.z())).norm();
  if (std::abs(p.x()) > ear_c_.x() + 2.0f) col *= 1.0f - 0.45f * (1.0f - smoothstep(0.6f, 1.0f, inner));
  return col;
}

V3 HeadPainter::albedo(const V3& p) const {
  V3 skin = p_.skin * (0.96f + 0.08f * vnoise(p.x() * 0.08f + 17.0f, p.y() * 0.08f + p.z() * 0.05f));
  V3 col = skin;
  if (p.z() > front_z_) {
    V2 q(p.x(), p.y());
    const float ex = 0.5f * p_.eye_distance;
    for (int s = -1; s <= 1; s += 2) {
      float d2 = (q - V2(s * (ex + 8.0f), -0.27f * p_.face_length)).squaredNorm();
      col = mix(col, col.cwiseProduct(V3(1.06f, 0.9f, 0.9f)), 0.7f * std::exp(-d2 / (2.0f * 15.0f * 15.0f)));
      float e2 = (q - V2(s * ex, 1.5f)).squaredNorm();
      col *= 1.0f - 0.2f * std::exp(-e2 / (2.0f * 10.0f * 10.0f));
    }
    col = paint_brows(q, col);
    col = paint_eye(q.x() < 0 ? f_.eye_r : f_.eye_l, q, col);
    col = paint_nose(q, col);
    col = paint_mouth(q, col);
  }
  col = paint_ear(p, col);
  col *= 1.0f - 0.18f * smoothstep(-p_.face_length + 5.0f, -p_.face_length - 15.0f, p.y());  // neck
  float hair = hair_coverage(p);
  if (hair > 0.0f) {
    float az = std::atan2(p.x(), p.z());
    float strands = 0.65f + 0.7f * vnoise(az * 180.0f, p.y() * 0.05f);
    col = mix(col, p_.hair * strands, hair);
  }
  return col;
}

Image bake_latlong_texture(const HeadPainter& painter, int width,
                           const std::function<Eigen::Vector3f(float u, float v)>& surface) {
  const int height = width / 2;
  Image tex(width, height, 3);
  mesh::parallel_rows(height, 0, [&](int j) {
    for (int i = 0; i < width; ++i) {
      V3 c = painter.albedo(surface((i + 0.5f) / width, (j + 0.5f) / height));
      for (int k = 0; k < 3; ++k) tex.at(i, j, k) = std::clamp(c[k], 0.0f, 1.0f);
    }
  });
  return tex;
}

}  // namespace lorgnette::synth
