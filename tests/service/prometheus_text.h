// A strict reader of Prometheus' text exposition format (version 0.0.4) for the /metrics tests:
// every line is a HELP or TYPE comment or a sample `name{label="value",...} number`; a sample's
// family must have had its TYPE line before it (a histogram's family takes its _bucket, _sum and
// _count samples); and histogram_errors() checks each histogram: buckets cumulative in `le`
// order, ending with le="+Inf", whose count equals _count. Throws with the offending line.
#pragma once
#include <cmath>
#include <map>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace lorgnette::service::test {

struct PromSample {
  std::string name;
  std::map<std::string, std::string> labels;
  double value = 0.0;
};

struct PromText {
  std::map<std::string, std::string> types;  // family -> counter | gauge | histogram | ...
  std::vector<PromSample> samples;

  // The value of the sample with exactly these labels; NaN when there is none.
  double value(const std::string& name, const std::map<std::string, std::string>& labels = {}) const {
    for (const auto& s : samples)
      if (s.name == name && s.labels == labels) return s.value;
    return std::nan("");
  }
};

inline std::string prom_family(const PromText& t, const std::string& name) {
  for (const char* suffix : {"_bucket", "_sum", "_count"}) {
    const std::string sfx = suffix;
    if (name.size() > sfx.size() && name.compare(name.size() - sfx.size(), sfx.size(), sfx) == 0) {
      const std::string base = name.substr(0, name.size() - sfx.size());
      auto it = t.types.find(base);
      if (it != t.types.end() && (it->second == "histogram" || it->second == "summary")) return base;
    }
  }
  return name;
}

inline PromText parse_prometheus(const std::string& text) {
  static const std::regex type_line(
      R"(# TYPE ([a-zA-Z_:][a-zA-Z0-9_:]*) (counter|gauge|histogram|summary|untyped))");
  static const std::regex help_line(R"(# HELP [a-zA-Z_:][a-zA-Z0-9_:]* .*)");
  static const std::regex sample_line(R"(([a-zA-Z_:][a-zA-Z0-9_:]*)(\{(.*)\})? (\S+))");
  static const std::regex label(R"(([a-zA-Z_][a-zA-Z0-9_]*)="((?:[^"\\]|\\.)*)\"(,|$))");
  PromText t;
  std::istringstream in(text);
  std::string line;
  std::smatch m;
  while (std::getline(in, line)) {
    if (line.empty() || std::regex_match(line, help_line)) continue;
    if (std::regex_match(line, m, type_line)) {
      if (!t.types.emplace(m[1], m[2]).second) throw std::runtime_error("a second TYPE line: " + line);
      continue;
    }
    if (!std::regex_match(line, m, sample_line)) throw std::runtime_error("not a metrics line: " + line);
    PromSample s;
    s.name = m[1];
    if (!t.types.count(prom_family(t, s.name))) throw std::runtime_error("a sample before its TYPE: " + line);
    std::string labels = m[3];
    for (std::smatch l; !labels.empty(); labels = l.suffix()) {
      if (!std::regex_search(labels, l, label) || l.position(0) != 0)
        throw std::runtime_error("bad labels: " + line);
      s.labels[l[1]] = l[2];
    }
    const std::string v = m[4];
    try {
      size_t used = 0;
      s.value = v == "+Inf" ? INFINITY : v == "-Inf" ? -INFINITY : std::stod(v, &used);
      if (v != "+Inf" && v != "-Inf" && used != v.size()) throw std::invalid_argument(v);
    } catch (const std::logic_error&) {
      throw std::runtime_error("bad value: " + line);
    }
    t.samples.push_back(std::move(s));
  }
  return t;
}

// What is wrong with the histograms in `t` (empty: nothing).
inline std::vector<std::string> histogram_errors(const PromText& t) {
  std::vector<std::string> errors;
  for (const auto& [family, type] : t.types) {
    if (type != "histogram") continue;
    std::map<std::map<std::string, std::string>, std::vector<std::pair<double, double>>> buckets;
    for (const auto& s : t.samples) {
      if (s.name != family + "_bucket") continue;
      auto key = s.labels;
      const std::string le = key["le"];
      key.erase("le");
      buckets[key].push_back({le == "+Inf" ? INFINITY : std::stod(le), s.value});
    }
    for (const auto& [key, b] : buckets) {
      for (size_t i = 1; i < b.size(); ++i)
        if (!(b[i].first > b[i - 1].first) || b[i].second < b[i - 1].second)
          errors.push_back(family + ": buckets not in le order or not cumulative");
      if (b.empty() || !std::isinf(b.back().first)) errors.push_back(family + ": no +Inf bucket");
      if (!b.empty() && t.value(family + "_count", key) != b.back().second)
        errors.push_back(family + ": the +Inf bucket differs from _count");
      if (std::isnan(t.value(family + "_sum", key))) errors.push_back(family + ": no _sum");
    }
  }
  return errors;
}

}  // namespace lorgnette::service::test
