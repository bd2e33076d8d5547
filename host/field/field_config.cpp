// FieldConfig JSON round-trip, validation and the flat parameter layout (see field_config.h).
#include "host/field/field_config.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

namespace lorgnette::field {
namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("invalid field configuration: " + what);
}

uint64_t round_up(uint64_t n, uint64_t m) { return (n + m - 1) / m * m; }

LayerShape layer(uint32_t in, uint32_t in_pad, uint32_t out, uint64_t* cursor) {
  LayerShape s;
  s.in = in;
  s.in_pad = in_pad;
  s.out = out;
  s.out_pad = pad4(out);
  s.offset = *cursor;
  *cursor += s.count();
  return s;
}

}  // namespace

nlohmann::json FieldConfig::to_json() const {
  return {{"levels", levels},
          {"features_per_level", features_per_level},
          {"log2_table_size", log2_table_size},
          {"base_resolution", base_resolution},
          {"finest_resolution", finest_resolution},
          {"density_hidden", density_hidden},
          {"geo_features", geo_features},
          {"color_hidden", color_hidden},
          {"color_hidden_layers", color_hidden_layers},
          {"sh_degree", sh_degree}};
}

FieldConfig FieldConfig::from_json(const nlohmann::json& j) {
  if (!j.is_object())
    throw std::invalid_argument("field configuration must be a JSON object, got: " + j.dump());
  FieldConfig c;
  auto get = [&j](const char* key, uint32_t& v) {
    if (!j.contains(key)) return;
    const auto& x = j.at(key);
    if (!x.is_number_integer() || x.get<int64_t>() < 0 || x.get<int64_t>() > int64_t(UINT32_MAX))
      throw std::invalid_argument(std::string("field configuration key '") + key +
                                  "' must be a non-negative integer, got " + x.dump());
    v = x.get<uint32_t>();
  };
  get("levels", c.levels);
  get("features_per_level", c.features_per_level);
  get("log2_table_size", c.log2_table_size);
  get("base_resolution", c.base_resolution);
  get("finest_resolution", c.finest_resolution);
  get("density_hidden", c.density_hidden);
  get("geo_features", c.geo_features);
  get("color_hidden", c.color_hidden);
  get("color_hidden_layers", c.color_hidden_layers);
  get("sh_degree", c.sh_degree);
  c.validate();
  return c;
}

void FieldConfig::validate() const {
  require(levels >= 1 && levels <= 32, "levels = " + std::to_string(levels) + " (expected 1..32)");
  require(features_per_level >= 1 && features_per_level <= 8,
          "features_per_level = " + std::to_string(features_per_level) + " (expected 1..8)");
  require(log2_table_size >= 8 && log2_table_size <= 24,
          "log2_table_size = " + std::to_string(log2_table_size) + " (expected 8..24)");
  require(base_resolution >= 2 && base_resolution <= 1u << 16,
          "base_resolution = " + std::to_string(base_resolution) + " (expected 2..65536)");
  require(
      finest_resolution >= base_resolution && finest_resolution <= 1u << 20,
      "finest_resolution = " + std::to_string(finest_resolution) + " (expected base_resolution..1048576)");
  require(density_hidden >= 1 && density_hidden <= 256,
          "density_hidden = " + std::to_string(density_hidden) + " (expected 1..256)");
  require(geo_features >= 1 && geo_features <= 64, "geo_features = " + std::to_string(geo_features) +
                                                       " (expected 1..64; feature 0 is the raw density)");
  require(color_hidden >= 1 && color_hidden <= 256,
          "color_hidden = " + std::to_string(color_hidden) + " (expected 1..256)");
  require(color_hidden_layers >= 1 && color_hidden_layers <= 8,
          "color_hidden_layers = " + std::to_string(color_hidden_layers) + " (expected 1..8)");
  require(sh_degree >= 1 && sh_degree <= 4, "sh_degree = " + std::to_string(sh_degree) + " (expected 1..4)");
  require(pad4(levels * features_per_level) <= 256, "levels * features_per_level must be at most 256");
}

bool FieldConfig::operator==(const FieldConfig& o) const { return to_json() == o.to_json(); }

uint64_t FieldConfig::param_count() const { return make_layout(*this).total; }

ParamLayout make_layout(const FieldConfig& cfg) {
  cfg.validate();
  ParamLayout lay;
  const uint64_t table = uint64_t(1) << cfg.log2_table_size;
  const double scale = cfg.levels > 1
                           ? std::log2(double(cfg.finest_resolution) / cfg.base_resolution) / (cfg.levels - 1)
                           : 0.0;
  uint64_t cursor = 0;
  for (uint32_t l = 0; l < cfg.levels; ++l) {
    HashLevel h;
    h.resolution = uint32_t(std::floor(cfg.base_resolution * std::exp2(l * scale) + 1e-6));
    const uint64_t v = uint64_t(h.resolution) + 1;
    h.dense = v * v * v <= table ? 1 : 0;
    h.size = uint32_t(h.dense ? v * v * v : table);
    h.offset = cursor;
    cursor = round_up(cursor + uint64_t(cfg.features_per_level) * h.size, 16);
    lay.levels.push_back(h);
  }
  lay.hash_count = cursor;
  require(cursor < (uint64_t(1) << 31),
          "the hash tables exceed 2^31 parameters: lower log2_table_size or levels");
  lay.enc_width = cfg.levels * cfg.features_per_level;
  lay.enc_pad = pad4(lay.enc_width);
  lay.sh_count = cfg.sh_degree * cfg.sh_degree;
  const uint32_t sh_pad = pad4(lay.sh_count), geo_pad = pad4(cfg.geo_features);
  lay.color_in_pad = sh_pad + geo_pad;
  lay.mlp_offset = cursor;
  lay.density[0] = layer(lay.enc_width, lay.enc_pad, cfg.density_hidden, &cursor);
  lay.density[1] = layer(cfg.density_hidden, pad4(cfg.density_hidden), cfg.geo_features, &cursor);
  lay.color.push_back(layer(lay.sh_count + cfg.geo_features, lay.color_in_pad, cfg.color_hidden, &cursor));
  for (uint32_t h = 1; h < cfg.color_hidden_layers; ++h)
    lay.color.push_back(layer(cfg.color_hidden, pad4(cfg.color_hidden), cfg.color_hidden, &cursor));
  lay.color.push_back(layer(cfg.color_hidden, pad4(cfg.color_hidden), 3, &cursor));
  lay.total = cursor;
  return lay;
}

}  // namespace lorgnette::field
