// The field's fused inference launch; see field_infer.h.
#include "host/field/field_infer.h"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "host/field/hashgrid.h"
#include "kernels/mlp/mlp_types.h"

namespace lorgnette::field {
namespace {
// Work-items (32 samples each) per work-group: 8 share one group's scratch (8 x 25 KiB with the
// default shapes, in L2). Fewer groups cost PoCL less scheduling: the process CPU time of `bench
// frames` at 480p was 0.95x with 8 or 16 than with 1 (and 0.96x with 32), same run.
constexpr size_t kGroup = 8;
}  // namespace

uint64_t FieldInfer::local_bytes(const ParamLayout& layout) {
  uint32_t hidden = layout.density[0].out_pad;
  for (const auto& L : layout.color) hidden = std::max(hidden, L.out_pad);
  const uint64_t rows = layout.enc_pad + layout.color_in_pad + 2 * uint64_t(hidden) + 4;  // see below
  return kGroup * rows * LGN_INFER_SLAB * sizeof(float);
}

bool FieldInfer::supports(const ParamLayout& layout, uint64_t local_mem_bytes) {
  return 2 + layout.color.size() <= LGN_INFER_MAX_LAYERS && local_bytes(layout) <= local_mem_bytes;
}

// Scratch rows: encoding | colour input (SH, padding, geo features) | hidden A | hidden B | RGB.
// Hidden layers alternate between A and B; the density hidden layer uses A before the colour net.
FieldInferParams make_infer_params(const FieldConfig& cfg, const ParamLayout& lay, uint32_t stride) {
  if (2 + lay.color.size() > LGN_INFER_MAX_LAYERS)
    throw std::invalid_argument("fused field inference supports up to " +
                                std::to_string(LGN_INFER_MAX_LAYERS - 2) + " colour layers, the config has " +
                                std::to_string(lay.color.size()));
  FieldInferParams p{};
  p.hash = make_hashgrid_params(cfg, lay, stride);
  p.sh_degree = cfg.sh_degree;
  p.sh_count = lay.sh_count;
  p.sh_pad = pad4(lay.sh_count);
  p.enc_rows = lay.enc_pad;
  p.sh_row = lay.enc_pad;
  const uint32_t geo_row = p.sh_row + p.sh_pad;
  uint32_t hidden = lay.density[0].out_pad;
  for (const auto& L : lay.color) hidden = std::max(hidden, L.out_pad);
  const uint32_t a_row = p.sh_row + lay.color_in_pad, b_row = a_row + hidden;
  p.rgb_row = b_row + hidden;
  p.rows = p.rgb_row + 4;
  p.raw_row = geo_row;
  auto add = [&p](const LayerShape& L, uint32_t act, uint32_t x_row, uint32_t y_row) {
    const uint32_t l = p.layers++;
    p.in[l] = L.in_pad;
    p.out[l] = L.out_pad;
    p.w_offset[l] = uint32_t(L.offset);
    p.act[l] = act;
    p.x_row[l] = x_row;
    p.y_row[l] = y_row;
  };
  add(lay.density[0], LGN_ACT_RELU, 0, a_row);
  add(lay.density[1], LGN_ACT_NONE, a_row, geo_row);
  uint32_t x_row = p.sh_row, y_row = a_row;
  for (size_t h = 0; h < lay.color.size(); ++h) {
    const bool last = h + 1 == lay.color.size();
    if (last) y_row = p.rgb_row;
    add(lay.color[h], last ? LGN_ACT_SIGMOID : LGN_ACT_RELU, x_row, y_row);
    x_row = y_row;
    y_row = y_row == a_row ? b_row : a_row;
  }
  return p;
}

FieldInfer::FieldInfer(cl::Runtime& rt, const FieldConfig& cfg, const ParamLayout& layout, uint32_t stride)
    : rt_(rt), base_(make_infer_params(cfg, layout, stride)) {
  kernel_ = cl::Kernel(rt.program("field/field_infer.cl"), "field_infer");
}

void FieldInfer::run(const cl::Buffer<float>& params, const cl::Buffer<float>& pos,
                     const cl::Buffer<float>& dir, uint32_t n, cl::Buffer<float>& sigma,
                     cl::Buffer<float>& rgb) {
  if (n == 0) return;
  FieldInferParams p = base_;
  p.hash.n = n;
  p.n16 = uint32_t(cl::round_up(n, 16));
  const size_t items = cl::round_up((p.n16 + LGN_INFER_SLAB - 1) / LGN_INFER_SLAB, kGroup);
  kernel_
      .args(p, params, pos, dir, sigma, rgb, cl::LocalBytes{kGroup * p.rows * LGN_INFER_SLAB * sizeof(float)})
      .launch(rt_, items, kGroup);
}

}  // namespace lorgnette::field
