// What the executor measures for /metrics: seconds per completed stage (a Prometheus histogram per
// stage: capture, train, fit) and failed jobs by stage and cause. Causes are the executor's reading
// of a worker's end (local_executor.h):
//   refused  - the product stopped with its own message (exit 1: a capture without enough views,
//              no face found for the fit, ...): the shopper's input, usually;
//   crashed  - the worker died of a signal other than a stop (SIGSEGV, SIGABRT, ...): a bug;
//   killed   - stopped (SIGKILL/SIGTERM/SIGINT: the OOM killer, an operator) more times than
//              --max-attempts allows;
//   exit_status - any other exit status;  start - the worker process could not be started.
// Counts live in the server process (reset at restart, as Prometheus counters may be). Thread-safe.
#pragma once
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace lorgnette::service {

class JobMetrics {
 public:
  // Upper bounds (seconds) of the histogram's buckets, from a skipped stage to an hour's training.
  static const std::vector<double>& stage_buckets();
  void observe_stage(const std::string& stage, double seconds);
  void count_failure(const std::string& stage, const std::string& cause);
  // Both metric families in Prometheus' text format, HELP and TYPE lines included.
  std::string prometheus_text() const;

 private:
  struct Histogram {
    std::vector<int64_t> counts;  // per bucket, not cumulative; the last one is +Inf
    double sum = 0.0;
    int64_t count = 0;
  };
  mutable std::mutex mutex_;
  std::map<std::string, Histogram> stages_;
  std::map<std::pair<std::string, std::string>, int64_t> failures_;
};

}  // namespace lorgnette::service
