// The shape of a neural field (hash encoding + density MLP + colour MLP) and of its optimiser,
// with JSON round-trip, and the flat parameter layout derived from it: where each hash level and
// each weight matrix lives inside the one parameter buffer the kernels and Adam operate on.
#pragma once
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

namespace lorgnette::field {

struct FieldConfig {
  uint32_t levels = 16, features_per_level = 2, log2_table_size = 19, base_resolution = 16;
  uint32_t finest_resolution = 2048;                // per-level scale derived from base/finest/levels
  uint32_t density_hidden = 64, geo_features = 16;  // density MLP 32 -> 64 -> 16 (out[0] = raw density)
  uint32_t color_hidden = 64, color_hidden_layers = 2, sh_degree = 4;  // (16 SH + 16) -> 64 -> 64 -> 3

  nlohmann::json to_json() const;
  static FieldConfig from_json(const nlohmann::json& j);  // missing keys keep their defaults
  void validate() const;                                  // throws std::invalid_argument naming the bad value
  uint64_t param_count() const;  // floats in the flat parameter vector (MLP widths padded to 4)
  uint64_t bytes() const { return param_count() * sizeof(float); }
  bool operator==(const FieldConfig& o) const;
};

struct AdamConfig {
  float lr = 1e-2f, beta1 = 0.9f, beta2 = 0.99f, eps = 1e-15f, mlp_weight_decay = 1e-6f;
  // Hash-table entries whose gradient is exactly zero in a step keep their value and moments
  // (Instant-NGP's sparse update; kernels/adam/adam_types.h says how it differs from tiny-cuda-nn's).
  // Off by default: on the 2-core CPU it saved no measurable time (docs/bench/training-throughput.md),
  // and the dense update is what the quality figures were measured with.
  bool sparse_hash = false;
};

// Round up to a multiple of 4: every MLP width is padded so the kernels work on 4-row blocks.
// Padded rows/columns are zero-initialised and receive exactly zero gradient, so they stay zero.
inline uint32_t pad4(uint32_t n) { return (n + 3u) & ~3u; }

// One hash-grid level inside the flat parameter vector: features stored planar,
// params[offset + f * size + entry].
struct HashLevel {
  uint32_t resolution = 0;  // cells per axis; vertices per axis = resolution + 1
  uint32_t size = 0;        // entries per feature
  uint32_t dense = 0;       // 1: direct indexing, 0: spatial hash
  uint64_t offset = 0;
};

// One dense layer y = act(W x), W row-major [out_pad][in_pad] (no bias, as tiny-cuda-nn).
struct LayerShape {
  uint32_t in = 0, out = 0;          // logical widths
  uint32_t in_pad = 0, out_pad = 0;  // stored widths (multiples of 4)
  uint64_t offset = 0;               // W[0][0] in the flat vector
  uint64_t count() const { return uint64_t(in_pad) * out_pad; }
};

struct ParamLayout {
  std::vector<HashLevel> levels;
  uint64_t hash_count = 0;              // hash parameters occupy [0, hash_count)
  uint32_t enc_width = 0, enc_pad = 0;  // levels * features, padded
  uint32_t sh_count = 0;                // sh_degree^2
  uint32_t color_in_pad = 0;            // sh_count + geo_pad
  LayerShape density[2];                // enc -> hidden -> geo
  std::vector<LayerShape> color;        // (sh + geo) -> hidden ... -> 3
  uint64_t mlp_offset = 0;              // MLP parameters occupy [mlp_offset, total)
  uint64_t total = 0;
};

ParamLayout make_layout(const FieldConfig& cfg);

}  // namespace lorgnette::field
