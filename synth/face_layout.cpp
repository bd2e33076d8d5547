// The procedural head's facial layout; see face_layout.h. The 68 points follow the proportions of
// the common 68-point mean face, re-expressed relative to the features they belong to (eye centre,
// nose bridge, mouth corners) so that the parameters move whole features consistently.
#include "synth/face_layout.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lorgnette::synth {
namespace {

using V2 = Eigen::Vector2f;

// Jaw contour 0..8 as fractions of (jaw half width, face length); 9..16 mirror 7..0.
constexpr float kJaw[9][2] = {{-1.000f, -0.076f}, {-0.992f, -0.239f}, {-0.960f, -0.402f},
                              {-0.911f, -0.559f}, {-0.815f, -0.702f}, {-0.659f, -0.822f},
                              {-0.465f, -0.914f}, {-0.244f, -0.983f}, {0.000f, -1.000f}};
// Brow (outer to inner): x offset from the eye centre (mm at a 28 mm eye), height fraction.
constexpr float kBrow[5][2] = {
    {-28.3f, 0.46f}, {-18.5f, 0.86f}, {-5.0f, 1.0f}, {8.8f, 0.96f}, {21.2f, 0.77f}};
// Upper lip 48..54 and lower lip 55..59: x as a fraction of the half width, y offset (mm at lip
// thickness 1) from the mouth-corner line.
constexpr float kUpperLip[7][2] = {{-1.0f, 0.0f},  {-0.605f, 6.2f}, {-0.232f, 9.0f}, {0.0f, 7.6f},
                                   {0.232f, 9.0f}, {0.605f, 6.2f},  {1.0f, 0.0f}};
constexpr float kLowerLip[5][2] = {
    {0.66f, -7.9f}, {0.31f, -11.2f}, {0.0f, -12.0f}, {-0.31f, -11.2f}, {-0.66f, -7.9f}};

}  // namespace

float lid_bump(float t) {
  t = std::clamp(t, 0.0f, 1.0f);
  return std::pow(std::max(0.0f, std::sin(float(M_PI) * t)), 0.85f);
}

V2 EyeShape::upper(float t) const {
  V2 base = outer + t * (inner - outer);
  return base + V2(0.0f, upper_height * lid_bump(t));
}

V2 EyeShape::lower(float t) const {
  V2 base = outer + t * (inner - outer);
  return base - V2(0.0f, lower_height * lid_bump(t));
}

float FaceLayout::lip_line_y(float x) const {
  float u = std::clamp(x / mouth_half_width, -1.0f, 1.0f);
  return mouth_y + lip_line_lift * (1.0f - u * u);
}

std::vector<V2> catmull_rom(const std::vector<V2>& pts, int per_segment) {
  std::vector<V2> out;
  if (pts.size() < 2) return pts;
  for (size_t i = 0; i + 1 < pts.size(); ++i) {
    V2 p0 = pts[i == 0 ? 0 : i - 1], p1 = pts[i], p2 = pts[i + 1];
    V2 p3 = pts[i + 2 < pts.size() ? i + 2 : i + 1];
    for (int s = 0; s < per_segment; ++s) {
      float t = float(s) / per_segment, t2 = t * t, t3 = t2 * t;
      out.push_back(0.5f * (2.0f * p1 + (p2 - p0) * t + (2.0f * p0 - 5.0f * p1 + 4.0f * p2 - p3) * t2 +
                            (3.0f * p1 - p0 - 3.0f * p2 + p3) * t3));
    }
  }
  out.push_back(pts.back());
  return out;
}

float polyline_distance(const std::vector<V2>& line, const V2& q, float* t) {
  float best = std::numeric_limits<float>::infinity(), best_t = 0.0f;
  for (size_t i = 0; i + 1 < line.size(); ++i) {
    V2 a = line[i], ab = line[i + 1] - a;
    float len2 = std::max(ab.squaredNorm(), 1e-12f);
    float s = std::clamp((q - a).dot(ab) / len2, 0.0f, 1.0f);
    float d = (a + s * ab - q).norm();
    if (d < best) {
      best = d;
      best_t = (float(i) + s) / float(line.size() - 1);
    }
  }
  if (t) *t = best_t;
  return best;
}

float curve_y_at(const std::vector<V2>& curve, float x) {
  for (size_t i = 0; i + 1 < curve.size(); ++i) {
    float x0 = curve[i].x(), x1 = curve[i + 1].x();
    if ((x >= x0 && x <= x1) || (x <= x0 && x >= x1)) {
      float s = std::abs(x1 - x0) < 1e-9f ? 0.0f : (x - x0) / (x1 - x0);
      return curve[i].y() + s * (curve[i + 1].y() - curve[i].y());
    }
  }
  return std::numeric_limits<float>::quiet_NaN();
}

FaceLayout make_face_layout(const HeadParams& p) {
  FaceLayout f;
  auto& L = f.ibug;
  const float jaw_hw = 0.49f * p.head_width, F = p.face_length;
  for (int i = 0; i < 9; ++i) {
    L[i] = V2(kJaw[i][0] * jaw_hw, kJaw[i][1] * F);
    L[16 - i] = V2(-L[i].x(), L[i].y());
  }
  const float ex = 0.5f * p.eye_distance, ew = p.eye_width, es = ew / 28.0f;
  for (int i = 0; i < 5; ++i) {
    L[17 + i] = V2(-ex + kBrow[i][0] * es, kBrow[i][1] * p.brow_height);
    L[26 - i] = V2(-L[17 + i].x(), L[17 + i].y());
  }
  // Nose: bridge (27) to tip (30) evenly, nostril base (31-35) below the tip.
  const float bridge_y = 0.17f * p.brow_height, tip_y = bridge_y - p.nose_length, nw = p.nose_width;
  for (int i = 0; i < 4; ++i) L[27 + i] = V2(0.0f, bridge_y - p.nose_length * i / 3.0f);
  L[31] = V2(-0.44f * nw, tip_y - 11.0f);
  L[32] = V2(-0.22f * nw, tip_y - 13.2f);
  L[33] = V2(0.0f, tip_y - 15.0f);
  L[34] = V2(0.22f * nw, tip_y - 13.2f);
  L[35] = V2(0.44f * nw, tip_y - 11.0f);
  f.nostril_r = V2(-0.25f * nw, tip_y - 11.8f);
  f.nostril_l = V2(0.25f * nw, tip_y - 11.8f);
  // Eyes: outer corners slightly higher (canthal tilt).
  f.eye_r = {V2(-ex - 0.5f * ew, 1.5f), V2(-ex + 0.5f * ew, 0.0f), 0.64f * p.eye_opening,
             0.36f * p.eye_opening};
  f.eye_l = {V2(ex + 0.5f * ew, 1.5f), V2(ex - 0.5f * ew, 0.0f), 0.64f * p.eye_opening,
             0.36f * p.eye_opening};
  L[36] = f.eye_r.outer, L[37] = f.eye_r.upper(1.0f / 3), L[38] = f.eye_r.upper(2.0f / 3),
  L[39] = f.eye_r.inner;
  L[40] = f.eye_r.lower(2.0f / 3), L[41] = f.eye_r.lower(1.0f / 3);
  L[42] = f.eye_l.inner, L[43] = f.eye_l.upper(2.0f / 3), L[44] = f.eye_l.upper(1.0f / 3),
  L[45] = f.eye_l.outer;
  L[46] = f.eye_l.lower(1.0f / 3), L[47] = f.eye_l.lower(2.0f / 3);
  f.iris_radius = 0.5f * p.iris_diameter;
  f.pupil_radius = 0.085f * ew;
  // Mouth.
  f.mouth_half_width = 0.5f * p.mouth_width;
  f.mouth_y = -0.585f * F;
  const float hw = f.mouth_half_width, lt = p.lip_thickness;
  for (int i = 0; i < 7; ++i) L[48 + i] = V2(kUpperLip[i][0] * hw, f.mouth_y + kUpperLip[i][1] * lt);
  for (int i = 0; i < 5; ++i) L[55 + i] = V2(kLowerLip[i][0] * hw, f.mouth_y + kLowerLip[i][1] * lt);
  const float inner_x[5] = {-0.845f, -0.24f, 0.0f, 0.24f, 0.845f};
  L[60] = V2(inner_x[0] * hw, f.lip_line_y(inner_x[0] * hw));
  for (int i = 1; i < 4; ++i) L[60 + i] = V2(inner_x[i] * hw, f.lip_line_y(inner_x[i] * hw) + 0.4f);
  L[64] = V2(inner_x[4] * hw, f.lip_line_y(inner_x[4] * hw));
  for (int i = 1; i < 4; ++i) L[68 - i] = V2(inner_x[i] * hw, f.lip_line_y(inner_x[i] * hw) - 0.4f);
  // Dense curves for painting.
  f.brow_r = catmull_rom({L[17], L[18], L[19], L[20], L[21]}, 12);
  f.brow_l = catmull_rom({L[26], L[25], L[24], L[23], L[22]}, 12);
  f.upper_lip_top = catmull_rom({L[48], L[49], L[50], L[51], L[52], L[53], L[54]}, 10);
  f.lower_lip_bottom = catmull_rom({L[54], L[55], L[56], L[57], L[58], L[59], L[48]}, 10);
  return f;
}

}  // namespace lorgnette::synth
