// Double-precision host reference of the Field (hash encoding, density and colour MLPs, sigma and
// RGB heads) and of its backward pass: the oracle the kernel tests compare against. The index and
// weight math comes from the shared kernel headers, so only the arithmetic precision differs.
#pragma once
#include <cstdint>
#include <vector>

#include "host/field/field_config.h"

namespace lorgnette::field::ref {

// Matrices of per-sample values are [row][n] (row-major, stride n), doubles.
using Rows = std::vector<double>;

// Samples: positions / directions structure-of-arrays with the given stride.
struct Samples {
  std::vector<float> pos, dir;
  uint32_t n = 0, stride = 0;
};

Rows encode(const ParamLayout& lay, const FieldConfig& cfg, const std::vector<float>& params,
            const Samples& s);
// d loss / d table for a given d loss / d enc ([enc_width][n]); returns the full-size gradient
// vector with only the hash part filled.
std::vector<double> encode_backward(const ParamLayout& lay, const FieldConfig& cfg, const Samples& s,
                                    const Rows& d_enc);

// y = act(W x) over all padded rows; act as in mlp_types.h.
Rows layer_forward(const LayerShape& L, const std::vector<float>& params, const Rows& x, uint32_t n,
                   uint32_t act);

struct Forward {
  Rows enc, dens_hidden, color_in;  // color_in: [SH (padded) | geo (padded)]
  std::vector<Rows> color_acts;     // outputs of each colour layer (last = sigmoid RGB, 4 rows)
  std::vector<double> sigma;        // n
  Rows rgb;                         // 3 x n
};
Forward forward(const ParamLayout& lay, const FieldConfig& cfg, const std::vector<float>& params,
                const Samples& s);

// Gradient of L = sum_i dsigma_i sigma_i + sum_{c,i} drgb_{c,i} rgb_{c,i} w.r.t. every parameter.
std::vector<double> backward(const ParamLayout& lay, const FieldConfig& cfg, const std::vector<float>& params,
                             const Samples& s, const Forward& f, const std::vector<double>& dsigma,
                             const Rows& drgb);

}  // namespace lorgnette::field::ref
