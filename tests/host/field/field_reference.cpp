// Double-precision host reference of the Field; see field_reference.h.
#include "field_reference.h"

#include <algorithm>
#include <cmath>

#include "kernels/hashgrid/hashgrid_types.h"
#include "kernels/mlp/mlp_types.h"

namespace lorgnette::field::ref {
namespace {

// Visits the 8 corners of every (sample, level): f(level, sample, entry, weight).
template <class Fn>
void for_corners(const ParamLayout& lay, const Samples& s, Fn fn) {
  for (uint32_t l = 0; l < lay.levels.size(); ++l) {
    const HashLevel& h = lay.levels[l];
    for (uint32_t i = 0; i < s.n; ++i) {
      lgn_uint cell[3];
      float frac[3];
      hashgrid_cell(h.resolution, s.pos[i], s.pos[s.stride + i], s.pos[2 * s.stride + i], cell, frac);
      for (lgn_uint c = 0; c < 8; ++c) {
        float w;
        lgn_uint e = hashgrid_corner(h.resolution, h.size, h.dense, cell, frac, c, &w);
        fn(l, i, e, double(w));
      }
    }
  }
}

// dx = W^T dz (all padded columns).
Rows layer_backward_input(const LayerShape& L, const std::vector<float>& params, const Rows& dz, uint32_t n) {
  Rows dx(size_t(L.in_pad) * n, 0.0);
  for (uint32_t j = 0; j < L.out_pad; ++j)
    for (uint32_t k = 0; k < L.in_pad; ++k) {
      const double w = params[L.offset + uint64_t(j) * L.in_pad + k];
      for (uint32_t i = 0; i < n; ++i) dx[size_t(k) * n + i] += w * dz[size_t(j) * n + i];
    }
  return dx;
}

void layer_weight_grad(const LayerShape& L, const Rows& x, const Rows& dz, uint32_t n,
                       std::vector<double>& g) {
  for (uint32_t j = 0; j < L.out_pad; ++j)
    for (uint32_t k = 0; k < L.in_pad; ++k) {
      double sum = 0;
      for (uint32_t i = 0; i < n; ++i) sum += dz[size_t(j) * n + i] * x[size_t(k) * n + i];
      g[L.offset + uint64_t(j) * L.in_pad + k] = sum;
    }
}

void relu_mask(Rows& d, const Rows& x) {
  for (size_t e = 0; e < d.size(); ++e)
    if (!(x[e] > 0)) d[e] = 0;
}

}  // namespace

Rows encode(const ParamLayout& lay, const FieldConfig& cfg, const std::vector<float>& params,
            const Samples& s) {
  const uint32_t F = cfg.features_per_level;
  Rows enc(size_t(lay.enc_pad) * s.n, 0.0);
  for_corners(lay, s, [&](uint32_t l, uint32_t i, uint32_t e, double w) {
    const HashLevel& h = lay.levels[l];
    for (uint32_t f = 0; f < F; ++f)
      enc[size_t(l * F + f) * s.n + i] += w * params[h.offset + f * h.size + e];
  });
  return enc;
}

std::vector<double> encode_backward(const ParamLayout& lay, const FieldConfig& cfg, const Samples& s,
                                    const Rows& d_enc) {
  const uint32_t F = cfg.features_per_level;
  std::vector<double> g(lay.total, 0.0);
  for_corners(lay, s, [&](uint32_t l, uint32_t i, uint32_t e, double w) {
    const HashLevel& h = lay.levels[l];
    for (uint32_t f = 0; f < F; ++f) g[h.offset + f * h.size + e] += w * d_enc[size_t(l * F + f) * s.n + i];
  });
  return g;
}

Rows layer_forward(const LayerShape& L, const std::vector<float>& params, const Rows& x, uint32_t n,
                   uint32_t act) {
  Rows y(size_t(L.out_pad) * n, 0.0);
  for (uint32_t j = 0; j < L.out_pad; ++j) {
    for (uint32_t k = 0; k < L.in_pad; ++k) {
      const double w = params[L.offset + uint64_t(j) * L.in_pad + k];
      for (uint32_t i = 0; i < n; ++i) y[size_t(j) * n + i] += w * x[size_t(k) * n + i];
    }
    for (uint32_t i = 0; i < n; ++i) y[size_t(j) * n + i] = lgn_activate_d(y[size_t(j) * n + i], act);
  }
  return y;
}

Forward forward(const ParamLayout& lay, const FieldConfig& cfg, const std::vector<float>& params,
                const Samples& s) {
  const uint32_t n = s.n, sh_pad = pad4(lay.sh_count);
  Forward f;
  f.enc = encode(lay, cfg, params, s);
  f.dens_hidden = layer_forward(lay.density[0], params, f.enc, n, LGN_ACT_RELU);
  Rows geo = layer_forward(lay.density[1], params, f.dens_hidden, n, LGN_ACT_NONE);
  f.color_in.assign(size_t(lay.color_in_pad) * n, 0.0);
  for (uint32_t i = 0; i < n; ++i) {
    float sh[16];
    sh_basis(s.dir[i], s.dir[s.stride + i], s.dir[2 * s.stride + i], cfg.sh_degree, sh);
    for (uint32_t c = 0; c < lay.sh_count; ++c) f.color_in[size_t(c) * n + i] = sh[c];
  }
  std::copy(geo.begin(), geo.end(), f.color_in.begin() + size_t(sh_pad) * n);
  f.sigma.resize(n);
  for (uint32_t i = 0; i < n; ++i) f.sigma[i] = lgn_sigma_from_raw_d(geo[i]);
  const Rows* x = &f.color_in;
  for (size_t h = 0; h < lay.color.size(); ++h) {
    const bool last = h + 1 == lay.color.size();
    f.color_acts.push_back(layer_forward(lay.color[h], params, *x, n, last ? LGN_ACT_SIGMOID : LGN_ACT_RELU));
    x = &f.color_acts.back();
  }
  f.rgb.assign(f.color_acts.back().begin(), f.color_acts.back().begin() + 3 * size_t(n));
  return f;
}

std::vector<double> backward(const ParamLayout& lay, const FieldConfig& cfg, const std::vector<float>& params,
                             const Samples& s, const Forward& f, const std::vector<double>& dsigma,
                             const Rows& drgb) {
  const uint32_t n = s.n, sh_pad = pad4(lay.sh_count);
  std::vector<double> g(lay.total, 0.0);
  Rows dz(4 * size_t(n), 0.0);
  for (size_t e = 0; e < 3 * size_t(n); ++e) {
    dz[e] = lgn_sigmoid_backward_d(drgb[e], f.color_acts.back()[e]);
  }
  for (size_t h = lay.color.size(); h-- > 0;) {
    const Rows& x = h == 0 ? f.color_in : f.color_acts[h - 1];
    layer_weight_grad(lay.color[h], x, dz, n, g);
    Rows dx = layer_backward_input(lay.color[h], params, dz, n);
    if (h > 0) relu_mask(dx, x);
    dz = std::move(dx);
  }
  // dz now holds d color_in; take the geo rows and add the sigma path on row 0.
  const uint32_t geo_pad = pad4(cfg.geo_features);
  Rows dgeo(dz.begin() + size_t(sh_pad) * n, dz.begin() + size_t(sh_pad + geo_pad) * n);
  for (uint32_t i = 0; i < n; ++i) {
    const double raw = f.color_in[size_t(sh_pad) * n + i];
    dgeo[i] += dsigma[i] * lgn_sigma_grad_d(raw, f.sigma[i]);
  }
  layer_weight_grad(lay.density[1], f.dens_hidden, dgeo, n, g);
  Rows dh = layer_backward_input(lay.density[1], params, dgeo, n);
  relu_mask(dh, f.dens_hidden);
  layer_weight_grad(lay.density[0], f.enc, dh, n, g);
  Rows denc = layer_backward_input(lay.density[0], params, dh, n);
  std::vector<double> gh = encode_backward(lay, cfg, s, denc);
  for (uint64_t e = 0; e < lay.hash_count; ++e) g[e] = gh[e];
  return g;
}

}  // namespace lorgnette::field::ref
