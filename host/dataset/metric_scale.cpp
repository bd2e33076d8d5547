// scale.json; see metric_scale.h.
#include "host/dataset/metric_scale.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "host/util/image_io.h"

namespace lorgnette::dataset {

void check_metric_scale(const MetricScale& s, const std::string& where) {
  if (!(std::isfinite(s.mm_per_unit) && s.mm_per_unit > 0))
    throw std::runtime_error(
        fmt::format("{}: mm_per_unit must be a positive number, found {}", where, s.mm_per_unit));
  if (!(std::isfinite(s.uncertainty) && s.uncertainty >= 0))
    throw std::runtime_error(
        fmt::format("{}: mm_per_unit_uncertainty must be a number >= 0, found {}", where, s.uncertainty));
  if (s.source.empty())
    throw std::runtime_error(fmt::format("{}: source must name what the scale came from", where));
}

void write_scale_json(const std::string& dataset_dir, const MetricScale& s) {
  check_metric_scale(s, "scale.json");
  nlohmann::json j = {{"source", s.source},
                      {"mm_per_unit", s.mm_per_unit},
                      {"mm_per_unit_uncertainty", s.uncertainty},
                      {"frames", s.frames}};
  write_text_file_atomic((std::filesystem::path(dataset_dir) / kScaleFile).string(), j.dump(2) + "\n");
}

std::optional<MetricScale> read_scale_json(const std::string& dataset_dir) {
  const std::filesystem::path p = std::filesystem::path(dataset_dir) / kScaleFile;
  if (!std::filesystem::exists(p)) return std::nullopt;
  const std::string where = fmt::format("'{}'", p.string());
  std::ifstream in(p);
  nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  auto bad = [&](const std::string& what) {
    return std::runtime_error(fmt::format(
        "{} {}; fix it or delete it (the scale is then unknown, as without a card)", where, what));
  };
  if (!in.good() && !in.eof()) throw bad("cannot be read");
  if (j.is_discarded() || !j.is_object()) throw bad("is not a JSON object");
  MetricScale s;
  try {
    s.source = j.at("source").get<std::string>();
    s.mm_per_unit = j.at("mm_per_unit").get<double>();
    s.uncertainty = j.value("mm_per_unit_uncertainty", 0.0);
    s.frames = j.value("frames", 0);
  } catch (const nlohmann::json::exception& e) {
    throw bad(fmt::format("lacks a field or has one of the wrong type ({})", e.what()));
  }
  try {
    check_metric_scale(s, where);
  } catch (const std::runtime_error& e) {
    throw bad(e.what());
  }
  return s;
}

}  // namespace lorgnette::dataset
