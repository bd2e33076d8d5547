// The admin endpoints (api.h): the queue as JSON and /metrics in Prometheus' text format
// (https://prometheus.io/docs/instrumenting/exposition_formats/): jobs by state, queue length,
// busy worker slots, stage seconds and failures by cause (job_metrics.h), responses by status and
// refused uploads by reason.
#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "service/api.h"

namespace lorgnette::service {

ApiResponse Api::queue() {
  nlohmann::json jobs = nlohmann::json::array();
  for (JobState s : {JobState::Running, JobState::Queued})
    for (const CaptureRecord& r : store_.with_state(s))
      jobs.push_back({{"id", r.id},
                      {"state", to_string(r.state)},
                      {"stage", r.stage},
                      {"progress", r.percent},
                      {"attempts", r.attempts},
                      {"queued_unix", r.queued_unix}});
  return {200, "application/json", nlohmann::json{{"jobs", jobs}}.dump(2) + "\n"};
}

ApiResponse Api::metrics() {
  std::string out;
  const auto counts = store_.count_by_state();
  out += "# HELP lorgnette_jobs Captures by job state.\n# TYPE lorgnette_jobs gauge\n";
  for (const auto& [state, n] : counts)
    out += fmt::format("lorgnette_jobs{{state=\"{}\"}} {}\n", to_string(state), n);
  out +=
      "# HELP lorgnette_queue_length Jobs waiting for a worker slot.\n# TYPE lorgnette_queue_length gauge\n";
  out += fmt::format("lorgnette_queue_length {}\n", counts.at(JobState::Queued));
  out += "# HELP lorgnette_workers_busy Worker slots running a job.\n# TYPE lorgnette_workers_busy gauge\n";
  out += fmt::format("lorgnette_workers_busy {}\n", executor_.running());
  if (const JobMetrics* m = executor_.metrics()) out += m->prometheus_text();
  std::lock_guard<std::mutex> lock(metrics_mutex_);
  out += "# HELP lorgnette_http_responses_total API responses by status.\n";
  out += "# TYPE lorgnette_http_responses_total counter\n";
  for (const auto& [status, n] : responses_by_status_)
    out += fmt::format("lorgnette_http_responses_total{{status=\"{}\"}} {}\n", status, n);
  out += "# HELP lorgnette_uploads_rejected_total Uploads refused, by reason.\n";
  out += "# TYPE lorgnette_uploads_rejected_total counter\n";
  for (const auto& [reason, n] : rejected_uploads_)
    out += fmt::format("lorgnette_uploads_rejected_total{{reason=\"{}\"}} {}\n", reason, n);
  return {200, "text/plain; version=0.0.4", out};
}

}  // namespace lorgnette::service
