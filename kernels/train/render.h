// Volume rendering of one ray from its compacted samples, forward and backward, shared by the
// training loss kernel and the host tests (the host build is the oracle). Samples are `step` apart;
// alpha_i = 1 - exp(-sigma_i * step), T_i = prod_{j<i} (1 - alpha_j), w_i = T_i * alpha_i,
// C = sum_i w_i c_i + T_end * bg: the compositing step of common/composite.h, shared with the
// inference marcher. Accumulation stops once T drops below min_transmittance (later
// samples get zero weight and zero gradient), as instant-ngp does.
//
// Loss (LOSS_L2_SRGB, the default): mean over rays and channels of (srgb(C) - srgb(target))^2 with
// C in linear RGB, so training minimises what PSNR on 8-bit sRGB images measures while compositing
// stays linear (physically right for the glasses compositing). LOSS_L2_LINEAR: the same on linear.
//
// Gradients (reverse accumulation, one ray): with g = dL/dC,
//   dL/dc_i     = w_i * g
//   dL/dsigma_i = step * g . (T_{i+1} c_i - (C - C_{<=i}))   where C_{<=i} = sum_{k<=i} w_k c_k
// (C includes the background term).
//
// Binary-opacity prior (mask-less captures with a room model): weight * a * (1 - a) per ray, a = 1 - T_end
// the ray's opacity, as a mean over rays (Neural Volumes' beta prior in a bounded form): a ray
// through the subject is opaque and one past it is clear, so semi-transparent haze and soft fringes
// that the room model could explain are pushed to 0 or 1. Its gradient, dL/dsigma_i = step * T_end *
// dL/da for the samples used, is added to the colour loss's; the ray's reported loss stays the
// colour loss (the PSNR the trainer prints).
//
// Room-explained clearing (with the prior): where the room model's colour behind the ray already
// matches the pixel, the subject's opacity there explains nothing the room does not, so the ray is
// pulled to clear instead of to 0 or 1: the prior per ray becomes
//   weight * ((1 - g) * a * (1 - a) + clear * g * a),   g = clamp(1 - e / tolerance, 0, 1),
// e the RMS sRGB difference between the room's colour and the pixel. Without it a frontal capture's
// wall, which the subject's fine grid can paint in its volume's rim as well as the coarse room model
// can behind it, is made opaque there by the binary push (docs/room-training.md, "The opacity prior
// and the room-explained clearing"). A pixel the room does not explain (g = 0) keeps the binary prior.
#pragma once
#include "common/cl_compat.h"
#include "common/composite.h"
#include "train/occupancy.h"
#include "train/train_types.h"

#ifndef __OPENCL_C_VERSION__
using std::pow;
#endif

LGN_INLINE float lgn_srgb_encode(float x) {
  x = fmin(fmax(x, 0.0f), 1.0f);
  return x <= 0.0031308f ? 12.92f * x : 1.055f * pow(x, 1.0f / 2.4f) - 0.055f;
}

LGN_INLINE float lgn_srgb_encode_deriv(float x) {
  if (x <= 0.0031308f) return x < 0.0f ? 0.0f : 12.92f;
  if (x >= 1.0f) return 0.0f;
  return (1.055f / 2.4f) * pow(x, 1.0f / 2.4f - 1.0f);
}

// Forward: colour (rgb) and opacity (1 - T_end) into out[0..3]; returns samples used.
LGN_INLINE lgn_uint render_ray_forward(LGN_GLOBAL const float* sigma, LGN_GLOBAL const float* rgb,
                                       lgn_uint stride, lgn_uint first, lgn_uint count, float step,
                                       float min_transmittance, const float* bg, float* out) {
  float T = 1.0f, r = 0.0f, g = 0.0f, b = 0.0f;
  lgn_uint used = 0;
  for (lgn_uint k = 0; k < count; ++k) {
    if (T < min_transmittance) break;
    lgn_uint i = first + k;
    float w = lgn_composite_segment(&T, sigma[i], step);
    r += w * rgb[i];
    g += w * rgb[stride + i];
    b += w * rgb[2u * stride + i];
    used = k + 1u;
  }
  out[0] = r + T * bg[0];
  out[1] = g + T * bg[1];
  out[2] = b + T * bg[2];
  out[3] = 1.0f - T;
  return used;
}

// Loss of one ray (not yet scaled by grad_scale) and dL/dC (scaled by grad_scale) into dC[0..2].
LGN_INLINE float render_ray_loss(const float* color, const float* target, lgn_uint loss_kind,
                                 float grad_scale, float* dC) {
  float loss = 0.0f;
  for (int c = 0; c < 3; ++c) {
    // A NaN colour must reach the loss (the sRGB clamp below would turn it into 0): the trainer
    // stops on a non-finite loss.
    if (color[c] != color[c]) {
      dC[0] = dC[1] = dC[2] = 0.0f;
      return color[c];
    }
    float diff, deriv;
    if (loss_kind == LOSS_L2_SRGB) {
      diff = lgn_srgb_encode(color[c]) - lgn_srgb_encode(target[c]);
      deriv = lgn_srgb_encode_deriv(color[c]);
    } else {
      diff = color[c] - target[c];
      deriv = 1.0f;
    }
    loss += diff * diff;
    dC[c] = grad_scale * 2.0f * diff * deriv;
  }
  return loss;
}

// Backward: writes dL/dsigma and dL/drgb for samples [first, first+count) (zero past `used`).
LGN_INLINE void render_ray_backward(LGN_GLOBAL const float* sigma, LGN_GLOBAL const float* rgb,
                                    lgn_uint stride, lgn_uint first, lgn_uint count, lgn_uint used,
                                    float step, const float* color, const float* dC, LGN_GLOBAL float* dsigma,
                                    LGN_GLOBAL float* drgb) {
  float T = 1.0f, acc_r = 0.0f, acc_g = 0.0f, acc_b = 0.0f;
  for (lgn_uint k = 0; k < count; ++k) {
    lgn_uint i = first + k;
    if (k >= used) {
      dsigma[i] = 0.0f;
      drgb[i] = 0.0f;
      drgb[stride + i] = 0.0f;
      drgb[2u * stride + i] = 0.0f;
      continue;
    }
    float cr = rgb[i], cg = rgb[stride + i], cb = rgb[2u * stride + i];
    float w = lgn_composite_segment(&T, sigma[i], step);  // T is now T_{i+1}
    acc_r += w * cr;
    acc_g += w * cg;
    acc_b += w * cb;
    drgb[i] = w * dC[0];
    drgb[stride + i] = w * dC[1];
    drgb[2u * stride + i] = w * dC[2];
    float sr = T * cr - (color[0] - acc_r), sg = T * cg - (color[1] - acc_g),
          sb = T * cb - (color[2] - acc_b);
    dsigma[i] = step * (dC[0] * sr + dC[1] * sg + dC[2] * sb);
  }
}

// RMS over the channels of the sRGB difference between two linear colours.
LGN_INLINE float render_ray_srgb_rms(const float* a, const float* b) {
  float e2 = 0.0f;
  for (int c = 0; c < 3; ++c) {
    const float d = lgn_srgb_encode(a[c]) - lgn_srgb_encode(b[c]);
    e2 += d * d;
  }
  return sqrt(e2 / 3.0f);
}

// The room gate g of the prior above: 1 where the room colour `bg` (linear) equals the pixel
// `target` (linear), falling linearly to 0 at an RMS sRGB difference of `tolerance` (0: no gate).
LGN_INLINE float render_ray_room_gate(const float* target, const float* bg, float tolerance) {
  if (!(tolerance > 0.0f)) return 0.0f;
  return fmin(fmax(1.0f - render_ray_srgb_rms(bg, target) / tolerance, 0.0f), 1.0f);
}

// The same gate, closed as far as the subject explains the pixel better than the room alone: the
// ray's render `color` (the subject composited over the room) nearer the pixel than `bg` by d (RMS
// sRGB) scales the gate by 1 - d / `margin` (0 at d >= margin; margin 0: the room gate alone). The
// clearing's premise is that the subject's opacity explains nothing the room does not; a subject
// whose own colour carries what the flat room lacks (hair strands shaded about the wall's colour, a
// face's shading and highlight before a wall of its colour) earns the ray, while a haze that paints
// the room's own colour (d about 0) is cleared as before. A ray left transparent renders the room's
// colour (d = 0), so the rule keeps a subject that formed and fills no hole that the colour loss
// does not fill. The gate is a weight, not differentiated (as the room gate).
LGN_INLINE float render_ray_clear_gate(const float* target, const float* bg, const float* color,
                                       float tolerance, float margin) {
  const float g = render_ray_room_gate(target, bg, tolerance);
  if (!(margin > 0.0f) || !(g > 0.0f)) return g;
  const float d = render_ray_srgb_rms(bg, target) - render_ray_srgb_rms(color, target);
  return g * fmin(fmax(1.0f - d / margin, 0.0f), 1.0f);
}

// Adds the opacity prior's gradient (weight * ((1 - g) a (1 - a) + clear g a) per ray, times
// `ray_scale`, the batch mean's 1 / rays) to dsigma of the `used` samples from `first`; returns the
// prior's value (unscaled). color[3] is the ray's opacity from render_ray_forward; gate = 0 gives the
// binary prior alone.
LGN_INLINE float render_ray_opacity_prior_dlda(float a, float weight, float clear, float gate,
                                               float ray_scale) {
  return weight * ray_scale * ((1.0f - gate) * (1.0f - 2.0f * a) + clear * gate);
}

LGN_INLINE float render_ray_opacity_prior(lgn_uint first, lgn_uint used, float step, const float* color,
                                          float weight, float clear, float gate, float ray_scale,
                                          LGN_GLOBAL float* dsigma) {
  const float a = color[3], T = 1.0f - a;
  const float dLda = render_ray_opacity_prior_dlda(a, weight, clear, gate, ray_scale);
  for (lgn_uint k = 0; k < used; ++k) dsigma[first + k] += step * T * dLda;
  return weight * ((1.0f - gate) * a * (1.0f - a) + clear * gate * a);
}

// 1 when the pixel `target` (linear) may be the subject's bare skin: its chromaticity (r, g over
// r + g + b) lies within `tolerance` of one of the `count` skin chromaticities `chroma` (pairs), each
// with up to SKIN_SHEEN_MAX of neutral light mixed in (the segment towards 1/3, 1/3), or it is too
// dark (luminance under `lum_floor`) for its chromaticity to say anything. Chromaticity, not the
// colour itself, since shading scales the skin's colour (the face in a side light, the shadow under
// the jaw) but leaves its chromaticity under the one light; a dark pixel counts as skin, since there
// noise decides its chromaticity. Only a pixel judged "not skin" earns the neck's keep zone the
// clearing (render_ray_opacity_prior_zones), so every doubt keeps the binary prior.
LGN_INLINE int render_ray_skin_like(const float* target, const float* chroma, lgn_uint count, float tolerance,
                                    float lum_floor) {
  const float lum = 0.2126f * target[0] + 0.7152f * target[1] + 0.0722f * target[2];
  const float sum = target[0] + target[1] + target[2];
  if (!(lum >= lum_floor) || !(sum > 0.0f)) return 1;
  const float r = target[0] / sum, g = target[1] / sum;
  for (lgn_uint k = 0; k < count; ++k) {
    const float cr = chroma[2u * k], cg = chroma[2u * k + 1u];
    const float sr = SKIN_SHEEN_MAX * (1.0f / 3.0f - cr), sg = SKIN_SHEEN_MAX * (1.0f / 3.0f - cg);
    const float len2 = sr * sr + sg * sg;
    const float t = len2 > 0.0f ? fmin(fmax(((r - cr) * sr + (g - cg) * sg) / len2, 0.0f), 1.0f) : 0.0f;
    const float dr = r - (cr + t * sr), dg = g - (cg + t * sg);
    if (dr * dr + dg * dg <= tolerance * tolerance) return 1;
  }
  return 0;
}

// The gate of the neck's keep cells (render_ray_opacity_prior_zones' keep_gate): the ray's gate
// where its pixel is no skin colour (render_ray_skin_like over the `count` chromaticities `chroma`;
// count 0: no skin colours known, or that rule off, so every pixel may be skin), else the gate times
// `far`, the share of the room's colour behind the ray that its surfaces beyond the subject's
// surroundings give (RAY_INFO_FAR, render_ray_share_beyond). The keep cells keep the binary prior
// because the room's body right below a head's box can explain a neck's pixel; a room colour from the
// wall far behind is no body's, so such a ray is the core's case and gets the gate as a core ray does
// (before a wall of the skin's own colour the slab beside the neck clears), while the neck's rays that
// cross its reach keep the binary prior whatever the gate (render_ray_opacity_prior_zones).
// A closed gate needs no skin test (most rays: the room does not explain them).
LGN_INLINE float render_ray_keep_gate(const float* target, float gate, const float* chroma, lgn_uint count,
                                      float tolerance, float lum_floor, float far) {
  if (!(gate > 0.0f)) return 0.0f;
  if (count > 0u && !render_ray_skin_like(target, chroma, count, tolerance, lum_floor)) return gate;
  return gate * fmin(fmax(far, 0.0f), 1.0f);
}

// Whether a sample at x (normalised to the model's box) lies in the subject's surroundings `near`
// (NearRegion: the box, and below its base plane only the column about the base's axis).
LGN_INLINE int render_near_contains(const NearRegion* near, const float* x) {
  int inside = 1;
  for (lgn_uint a = 0; a < 3u; ++a) inside = inside && x[a] >= near->lo[a] && x[a] <= near->hi[a];
  if (!inside || !(near->base_radius > 0.0f)) return inside;
  float d[3], along = 0.0f, d2 = 0.0f;
  for (lgn_uint a = 0; a < 3u; ++a) d[a] = x[a] - near->base[a], along += d[a] * near->up[a];
  if (along >= 0.0f) return 1;
  for (lgn_uint a = 0; a < 3u; ++a) d2 += d[a] * d[a];
  return d2 - along * along <= near->base_radius * near->base_radius;
}

// The share of a ray's colour that its samples outside the subject's surroundings `near` (positions
// normalised to the model's box) and the background give: 1 - the summed weights w_i of the samples
// inside them, composited and stopped early as render_ray_forward does. The room model's samples near
// the subject (its neck's base below a head's box) against those of the wall far behind.
LGN_INLINE float render_ray_share_beyond(LGN_GLOBAL const float* sigma, LGN_GLOBAL const float* pos,
                                         lgn_uint stride, lgn_uint first, lgn_uint count, float step,
                                         float min_transmittance, const NearRegion* near) {
  float T = 1.0f, near_w = 0.0f;
  for (lgn_uint k = 0; k < count; ++k) {
    if (T < min_transmittance) break;
    const lgn_uint i = first + k;
    const float w = lgn_composite_segment(&T, sigma[i], step);
    const float x[3] = {pos[i], pos[stride + i], pos[2u * stride + i]};
    if (render_near_contains(near, x)) near_w += w;
  }
  return fmin(fmax(1.0f - near_w, 0.0f), 1.0f);
}

// The same with prior zones: four bitfields of `res`^3 cells over the model's box, one after the other
// (occ_word_count(res) words each; positions `pos` SoA with `stride`, normalised to the box). Samples
// in the first field's cells ("keep") get the gate `keep_gate`: where the room model's own
// subject-coloured surface lies right behind the subject (the body below a head box, behind the
// neck) the ray's gate would clear the subject there too, so the caller passes 0 (the binary prior)
// unless the pixel is no colour of the subject's skin (render_ray_skin_like): such a ray passes no
// bare neck (a visual-hull argument), so the room's explaining it is no longer ambiguous; or unless
// the room's colour comes from beyond the body (render_ray_keep_gate). Samples in the second field's
// cells ("lean", the head volume's margin beyond the bare head) get the gate raised to at least
// `lean_gate`: there the binary prior no longer makes a haze that the room does not yet explain
// solid, so matter beyond the head must earn its place through the colour loss. The rest get the
// ray's gate.
// The third field ("solid") is the subject's certain interior (behind a face's skin, a neck's core).
// A ray that crosses it ends in the subject before it reaches the wall, and the room model holds
// only what lies beyond the subject's volume: whatever its colour matches, the room cannot explain
// that ray (a pale face before a pale wall). So no sample of such a ray gets the room's gate (the
// binary prior, as in "keep"), and its samples in the solid cells get a pull of `solid_pull` x the
// weight towards an opaque ray, which fills a hole there that the colour loss cannot tell from the
// wall. The crossing is judged over all `count` samples of the ray, not only the `used` ones in
// front of its opaque surface: a ray that the skin makes opaque before the interior still crosses it.
// The fourth field ("reach", holding the third) is where that crossing is judged: the interior grown
// towards the skin (BackgroundOptions::solid_reach_mm), so a ray that passes over the top of the
// skull through its hair, short of the interior, is the subject's too. The pull stays in the
// interior, except in the keep cells: there the reach (the neck's core grown towards its skin) gets
// `keep_pull` x the weight towards an opaque ray (BackgroundOptions::keep_pull).
LGN_INLINE void render_ray_opacity_prior_zones(lgn_uint first, lgn_uint count, lgn_uint used, float step,
                                               const float* color, float weight, float clear, float gate,
                                               float keep_gate, float keep_pull, float lean_gate,
                                               float solid_pull, float ray_scale, LGN_GLOBAL const float* pos,
                                               lgn_uint stride, LGN_GLOBAL const lgn_uint* zone_bits,
                                               lgn_uint res, LGN_GLOBAL float* dsigma) {
  LGN_GLOBAL const lgn_uint* lean_bits = zone_bits + occ_word_count(res);
  LGN_GLOBAL const lgn_uint* solid_bits = zone_bits + 2u * occ_word_count(res);
  LGN_GLOBAL const lgn_uint* reach_bits = zone_bits + 3u * occ_word_count(res);
  int crosses = 0;
  for (lgn_uint k = 0; k < count && !crosses; ++k) {
    const lgn_uint i = first + k;
    crosses = occ_test(reach_bits, res, pos[i], pos[stride + i], pos[2u * stride + i]);
  }
  const float a = color[3], T = 1.0f - a;
  const float binary = render_ray_opacity_prior_dlda(a, weight, clear, 0.0f, ray_scale);
  const float gated = crosses ? binary : render_ray_opacity_prior_dlda(a, weight, clear, gate, ray_scale);
  const float keep = crosses ? binary : render_ray_opacity_prior_dlda(a, weight, clear, keep_gate, ray_scale);
  const float lean =
      crosses ? binary : render_ray_opacity_prior_dlda(a, weight, clear, fmax(gate, lean_gate), ray_scale);
  const float solid = -solid_pull * weight * ray_scale;
  const float neck = keep - keep_pull * weight * ray_scale;
  for (lgn_uint k = 0; k < used; ++k) {
    const lgn_uint i = first + k;
    const float x = pos[i], y = pos[stride + i], z = pos[2u * stride + i];
    const float d = occ_test(solid_bits, res, x, y, z) ? solid
                    : occ_test(zone_bits, res, x, y, z)
                        ? (keep_pull > 0.0f && occ_test(reach_bits, res, x, y, z) ? neck : keep)
                    : occ_test(lean_bits, res, x, y, z) ? lean
                                                        : gated;
    dsigma[i] += step * T * d;
  }
}
