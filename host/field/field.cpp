// The Field: parameter initialisation, the forward chain (hash encoding -> density MLP -> sigma;
// SH(direction) + geometry features -> colour MLP -> RGB), its backward chain and Adam.
#include "host/field/field.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "host/field/adam.h"
#include "host/field/field_infer.h"
#include "host/field/hashgrid.h"
#include "host/field/mlp.h"

namespace lorgnette::field {
namespace {

// Uniform in [-a, a) from the top 24 bits of a 64-bit Mersenne Twister: the same stream on every
// platform (std::uniform_real_distribution is implementation-defined).
float uniform(std::mt19937_64& rng, float a) {
  return (float(rng() >> 40) * (1.0f / 16777216.0f) * 2.0f - 1.0f) * a;
}

// Xavier-uniform weights (tiny-cuda-nn's default) on the logical rows/columns; padding stays zero.
void init_layer(const LayerShape& L, std::vector<float>& params, std::mt19937_64& rng, uint32_t gap_begin = 0,
                uint32_t gap_end = 0) {
  const float a = std::sqrt(6.0f / float(L.in + L.out));
  for (uint32_t j = 0; j < L.out; ++j)
    for (uint32_t k = 0, used = 0; k < L.in_pad && used < L.in; ++k) {
      if (k >= gap_begin && k < gap_end) continue;
      params[L.offset + uint64_t(j) * L.in_pad + k] = uniform(rng, a);
      ++used;
    }
}

}  // namespace

Field::Field(cl::Runtime& rt, const FieldConfig& cfg, uint32_t max_batch, uint64_t seed, bool deterministic,
             KernelVariant variant)
    : rt_(rt), cfg_(cfg), layout_(make_layout(cfg)), deterministic_(deterministic) {
  if (max_batch == 0 || max_batch > (1u << 24))
    throw std::invalid_argument("Field max_batch = " + std::to_string(max_batch) + " (expected 1..16777216)");
  max_batch_ = uint32_t(cl::round_up(max_batch, 64));
  // Per-sample arrays are rows of max_batch_ floats. A power-of-two row length puts every row of a
  // slab in the same cache sets (rows 2^k floats apart), so the layered MLP and the hash encoding
  // thrash the cache; 64 spare samples break the alignment.
  if (max_batch_ >= 4096 && (max_batch_ & (max_batch_ - 1)) == 0) max_batch_ += 64;
  const uint64_t P = layout_.total;
  plan_rows();
  uint32_t largest = 16;
  for (const auto& L : layout_.density) largest = std::max<uint32_t>(largest, uint32_t(L.count()));
  for (const auto& L : layout_.color) largest = std::max<uint32_t>(largest, uint32_t(L.count()));
  params_ = cl::Buffer<float>(rt, P);
  grads_ = cl::Buffer<float>(rt, P);
  adam_m_ = cl::Buffer<float>(rt, P);
  adam_v_ = cl::Buffer<float>(rt, P);
  for (auto* b : {&grads_, &adam_m_, &adam_v_}) b->fill(rt, 0.0f);

  hash_ = std::make_unique<HashGrid>(rt, cfg_, layout_, max_batch_, variant);
  uint32_t largest_padded = 0;  // in_pad * out_pad: the local-weights chain's scratch
  for (const auto& L : layout_.density) largest_padded = std::max(largest_padded, L.in_pad * L.out_pad);
  for (const auto& L : layout_.color) largest_padded = std::max(largest_padded, L.in_pad * L.out_pad);
  mlp_ = std::make_unique<Mlp>(rt, max_batch_, variant, largest_padded);
  dw_partial_ = cl::Buffer<float>(rt, size_t(mlp_->max_grad_chunks()) * largest);
  adam_ = std::make_unique<Adam>(rt);
  if (!use_gpu_variant(rt, variant) && FieldInfer::supports(layout_, rt.device().local_mem_bytes))
    infer_ = std::make_unique<FieldInfer>(rt, cfg_, layout_, max_batch_);
  else
    ensure_layered_buffers();

  std::mt19937_64 rng(seed);
  std::vector<float> init(P, 0.0f);
  for (uint64_t i = 0; i < layout_.hash_count; ++i) init[i] = uniform(rng, 1e-4f);
  init_layer(layout_.density[0], init, rng);
  init_layer(layout_.density[1], init, rng);
  init_layer(layout_.color[0], init, rng, layout_.sh_count, pad4(layout_.sh_count));
  for (size_t h = 1; h < layout_.color.size(); ++h) init_layer(layout_.color[h], init, rng);
  params_.write(rt, init);
}

void Field::plan_rows() {
  ChainPlan plan = plan_chain(layout_, max_batch_);
  chain_ = plan.chain;
  color_in_row_ = plan.color_in_row;
  geo_row_ = plan.geo_row;
  rgb_row_ = plan.rgb_row;
  rows_ = plan.rows;
}

Field::~Field() = default;

void Field::ensure_layered_buffers() {
  if (acts_.size() > 0) return;
  const size_t S = max_batch_;
  acts_ = cl::Buffer<float>(rt_, rows_ * S);
  deltas_ = cl::Buffer<float>(rt_, rows_ * S);
  pos_copy_ = cl::Buffer<float>(rt_, 3 * S);
  // Padded rows are never written by the kernels and must read as zero.
  for (auto* b : {&acts_, &deltas_, &pos_copy_}) b->fill(rt_, 0.0f);
}

void Field::check_batch(const char* what, uint32_t n) const {
  if (n > max_batch_)
    throw std::invalid_argument(std::string("Field::") + what + ": " + std::to_string(n) +
                                " samples exceed max_batch " + std::to_string(max_batch_) +
                                ": split the batch or construct the Field with a larger max_batch");
}

static void check_size(const char* what, const cl::Buffer<float>& b, size_t need) {
  if (b.size() < need)
    throw std::invalid_argument(std::string("Field: buffer ") + what + " holds " + std::to_string(b.size()) +
                                " floats but needs " + std::to_string(need) +
                                " (per-sample arrays have stride max_batch)");
}

void Field::density(const cl::Buffer<float>& pos, uint32_t n, cl::Buffer<float>& sigma) {
  check_batch("density", n);
  check_size("pos", pos, 3 * size_t(max_batch_));
  check_size("sigma", sigma, n);
  pending_backward_n_ = 0;
  if (n == 0) return;
  ensure_layered_buffers();
  hash_->encode(params_, pos, n, acts_);
  MlpChainParams c = chain_;
  c.layers = 2;
  c.out[1] = 4;  // only the block holding the raw density
  mlp_->chain_forward(c, n, params_, acts_);
  mlp_->sigma(acts_, geo_row_, n, sigma);
}

void Field::forward(const cl::Buffer<float>& pos, const cl::Buffer<float>& dir, uint32_t n,
                    cl::Buffer<float>& sigma, cl::Buffer<float>& rgb, bool keep_for_backward) {
  check_batch("forward", n);
  const size_t S = max_batch_;
  check_size("pos", pos, 3 * S);
  check_size("dir", dir, 3 * S);
  check_size("sigma", sigma, n);
  check_size("rgb", rgb, 3 * S);
  pending_backward_n_ = 0;
  if (n == 0) return;
  if (infer_ && !keep_for_backward) {
    infer_->run(params_, pos, dir, n, sigma, rgb);
    return;
  }
  ensure_layered_buffers();
  hash_->encode(params_, pos, n, acts_);
  mlp_->sh_encode(dir, n, layout_.sh_count, acts_, color_in_row_);
  mlp_->chain_forward(chain_, n, params_, acts_);
  mlp_->sigma(acts_, geo_row_, n, sigma);
  rgb.copy_from(rt_, acts_, 3 * S, rgb_row_ * S, 0);
  if (keep_for_backward) {
    pos_copy_.copy_from(rt_, pos, 3 * S);
    pending_backward_n_ = n;
  }
}

void Field::backward(const cl::Buffer<float>& dL_dsigma, const cl::Buffer<float>& dL_drgb, uint32_t n) {
  if (n == 0 || n != pending_backward_n_)
    throw std::logic_error("Field::backward(n = " + std::to_string(n) +
                           ") must follow forward(..., keep_for_backward = true) with the same n and "
                           "no density()/forward() call in between (last kept n = " +
                           std::to_string(pending_backward_n_) + ")");
  check_size("dL_dsigma", dL_dsigma, n);
  check_size("dL_drgb", dL_drgb, 3 * size_t(max_batch_));
  mlp_->chain_backward(chain_, n, params_, acts_, deltas_, dL_dsigma, dL_drgb);
  const LayerShape* shapes[LGN_MLP_MAX_LAYERS] = {&layout_.density[0], &layout_.density[1]};
  for (size_t h = 0; h < layout_.color.size(); ++h) shapes[2 + h] = &layout_.color[h];
  for (uint32_t l = 0; l < chain_.layers; ++l)
    mlp_->weight_grad(*shapes[l], {&acts_, chain_.x_row[l], &deltas_, chain_.dy_row[l]}, n, dw_partial_,
                      grads_);
  // Encoding deltas are rows 0.. of deltas_.
  hash_->backward(pos_copy_, deltas_, n, grads_, deterministic_, hash_grads_zero_);
  hash_grads_zero_ = false;
}

void Field::adam_step(const AdamConfig& adam) {
  ++adam_t_;
  AdamParams p = make_adam_params(adam, adam_t_, uint32_t(layout_.total), uint32_t(layout_.mlp_offset));
  p.clear_below = uint32_t(layout_.hash_count);  // the next hash backward accumulates into zeros
  p.skip_zero_below = adam.sparse_hash ? uint32_t(layout_.hash_count) : 0u;
  adam_->step(p, params_, grads_, adam_m_, adam_v_);
  hash_grads_zero_ = true;
}

std::vector<float> Field::download_params() const { return params_.read(rt_); }
std::vector<float> Field::download_gradients() const { return grads_.read(rt_); }

void Field::upload_params(const std::vector<float>& params) {
  if (params.size() != layout_.total)
    throw std::invalid_argument("Field::upload_params: got " + std::to_string(params.size()) +
                                " parameters but this configuration has " + std::to_string(layout_.total) +
                                " (was the snapshot written with another FieldConfig?)");
  params_.write(rt_, params);
  grads_.fill(rt_, 0.0f);
  hash_grads_zero_ = true;
  adam_m_.fill(rt_, 0.0f);
  adam_v_.fill(rt_, 0.0f);
  adam_t_ = 0;
}

OptimiserState Field::download_optimiser() const { return {adam_m_.read(rt_), adam_v_.read(rt_), adam_t_}; }

void Field::restore(const std::vector<float>& params, const OptimiserState& adam) {
  if (adam.m.size() != layout_.total || adam.v.size() != layout_.total)
    throw std::invalid_argument("Field::restore: the optimiser state has " + std::to_string(adam.m.size()) +
                                " moments but this configuration has " + std::to_string(layout_.total) +
                                " parameters");
  upload_params(params);  // checks the size; zeroes the gradients (adam_step cleared them too)
  adam_m_.write(rt_, adam.m);
  adam_v_.write(rt_, adam.v);
  adam_t_ = adam.t;
}

}  // namespace lorgnette::field
