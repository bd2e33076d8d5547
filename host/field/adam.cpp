// Adam launches; see adam.h.
#include "host/field/adam.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace lorgnette::field {

AdamParams make_adam_params(const AdamConfig& cfg, uint64_t t, uint32_t count, uint32_t mlp_offset) {
  if (!(cfg.lr > 0) || !(cfg.beta1 >= 0 && cfg.beta1 < 1) || !(cfg.beta2 >= 0 && cfg.beta2 < 1) ||
      !(cfg.eps >= 0) || !(cfg.mlp_weight_decay >= 0))
    throw std::invalid_argument(
        "invalid Adam configuration: need lr > 0, 0 <= beta1, beta2 < 1, eps >= 0, "
        "weight decay >= 0 (lr=" +
        std::to_string(cfg.lr) + ")");
  AdamParams p{};
  p.count = count;
  p.mlp_offset = mlp_offset;
  p.lr = cfg.lr;
  p.beta1 = cfg.beta1;
  p.beta2 = cfg.beta2;
  p.eps = cfg.eps;
  p.weight_decay = cfg.mlp_weight_decay;
  p.bias1 = float(1.0 - std::pow(double(cfg.beta1), double(t)));
  p.bias2 = float(1.0 - std::pow(double(cfg.beta2), double(t)));
  return p;
}

Adam::Adam(cl::Runtime& rt) : rt_(rt), step_(rt.program("adam/adam.cl"), "adam_step") {}

void Adam::step(const AdamParams& p, cl::Buffer<float>& params, cl::Buffer<float>& grads,
                cl::Buffer<float>& m, cl::Buffer<float>& v) {
  if (p.clear_below > p.count)
    throw std::invalid_argument("Adam::step: clear_below " + std::to_string(p.clear_below) + " exceeds the " +
                                std::to_string(p.count) + " parameters");
  if (p.skip_zero_below > p.count)
    throw std::invalid_argument("Adam::step: skip_zero_below " + std::to_string(p.skip_zero_below) +
                                " exceeds the " + std::to_string(p.count) + " parameters");
  step_.args(p, params, grads, m, v).launch(rt_, p.count, 256);
}

}  // namespace lorgnette::field
