// Stage histograms and failure counters (job_metrics.h), written in Prometheus' text exposition
// format: cumulative `_bucket{le=...}` lines ending with le="+Inf", then `_sum` and `_count`.
#include "service/job_metrics.h"

#include <fmt/format.h>

namespace lorgnette::service {
namespace {

// A label value as the format requires: backslash, double quote and newline escaped (stage names
// come from a worker's progress file).
std::string label(const std::string& v) {
  std::string out;
  for (char c : v) {
    if (c == '\\' || c == '"') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out;
}

}  // namespace

const std::vector<double>& JobMetrics::stage_buckets() {
  static const std::vector<double> b = {1, 5, 15, 30, 60, 120, 300, 600, 1200, 1800, 3600};
  return b;
}

void JobMetrics::observe_stage(const std::string& stage, double seconds) {
  if (stage.empty() || !(seconds >= 0.0)) return;
  std::lock_guard<std::mutex> lock(mutex_);
  Histogram& h = stages_[stage];
  const auto& bounds = stage_buckets();
  if (h.counts.empty()) h.counts.assign(bounds.size() + 1, 0);
  size_t i = 0;
  while (i < bounds.size() && seconds > bounds[i]) ++i;
  ++h.counts[i];
  h.sum += seconds;
  ++h.count;
}

void JobMetrics::count_failure(const std::string& stage, const std::string& cause) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++failures_[{stage.empty() ? "start" : stage, cause}];
}

std::string JobMetrics::prometheus_text() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::string out =
      "# HELP lorgnette_stage_seconds Seconds of each completed stage, as the executor sees it.\n"
      "# TYPE lorgnette_stage_seconds histogram\n";
  const auto& bounds = stage_buckets();
  for (const auto& [stage, h] : stages_) {
    int64_t cumulative = 0;
    for (size_t i = 0; i < h.counts.size(); ++i) {
      cumulative += h.counts[i];
      const std::string le = i < bounds.size() ? fmt::format("{}", bounds[i]) : "+Inf";
      out += fmt::format("lorgnette_stage_seconds_bucket{{stage=\"{}\",le=\"{}\"}} {}\n", label(stage), le,
                         cumulative);
    }
    out += fmt::format("lorgnette_stage_seconds_sum{{stage=\"{}\"}} {}\n", label(stage), h.sum);
    out += fmt::format("lorgnette_stage_seconds_count{{stage=\"{}\"}} {}\n", label(stage), h.count);
  }
  out +=
      "# HELP lorgnette_job_failures_total Failed jobs by the stage they failed in and the cause.\n"
      "# TYPE lorgnette_job_failures_total counter\n";
  for (const auto& [key, n] : failures_)
    out += fmt::format("lorgnette_job_failures_total{{stage=\"{}\",cause=\"{}\"}} {}\n", label(key.first),
                       label(key.second), n);
  return out;
}

}  // namespace lorgnette::service
