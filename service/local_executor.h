// The local executor: N worker slots on this machine, each job a child process running `lorgnette
// job run <capture folder>` (child_process.h), so a crash in a stage (a decoder on a shopper's
// bytes, a loader) fails one job and never the server. It takes queued jobs from the store, copies
// each worker's progress.json into the store (the server stays the only writer of job state), and
// decides what a worker's end means:
//   exit 0 -> finished; exit 1 -> failed with the product's message; exit 75 (interrupted) -> queued;
//   killed by SIGKILL/SIGTERM/SIGINT (an operator, the OOM killer, a shutdown) -> queued again while
//   attempts remain; any other signal (a crash) or status -> failed, saying so.
// A job it runs is its own in the store (owner and lease, job_store.h): it writes a running job's
// row only while it owns it, and kills the worker of a row deleted meanwhile (by any server). At
// start, reconcile() hands back to the queue the running jobs of its own earlier process (their
// workers died with it) and those whose lease expired (another server died); tick() keeps doing
// the latter. Each stage resumes after its last finished stage.
#pragma once
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "service/child_process.h"
#include "service/executor.h"
#include "service/job_store.h"

namespace lorgnette::service {

struct LocalExecutorOptions {
  int slots = 1;                          // workers at once: one per GPU, or one on a CPU
  int max_attempts = 3;                   // worker starts per job before a killed job fails
  std::string data_dir;                   // capture folders are data_dir/captures/<id>
  std::string worker_exe;                 // the lorgnette binary ("" = this executable)
  std::vector<std::string> global_flags;  // passed before `job run` (e.g. --kernel-cache DIR)
  LeaseSettings lease;                    // who this server is, and its jobs' lease
};

class LocalExecutor final : public Executor {
 public:
  LocalExecutor(JobStore& store, LocalExecutorOptions options);
  ~LocalExecutor();  // kills and reaps running workers (their jobs stay "running" until reconcile)

  // Adopted running jobs (this server's earlier process's, or with an expired lease) back to the
  // queue; returns how many.
  int reconcile() override;
  // One pass: record ended workers and the progress of running ones, then start queued jobs in the
  // free slots. Thread-safe; the server calls it from one loop every fraction of a second.
  void tick() override;
  // Stops the worker of `id` if it has one (a deleted capture) and forgets it.
  void cancel(const std::string& id) override;
  // Asks every worker to stop after its current step (SIGTERM; their jobs go back to the queue) and
  // starts no new ones from then on: the server is shutting down.
  void interrupt_all() override;
  int running() const override;
  pid_t worker_pid(const std::string& id) const;  // -1 when none
  // Stage seconds and failures by cause (job_metrics.h), measured at each tick: a stage's seconds
  // run from the tick that first sees it in progress.json to the one that sees the next stage or
  // the job finished, so they are exact to a tick (0.2 s in `serve`). A stage a resumed job skips
  // (its output already there) is counted, near zero, when a tick happens to see it.
  const JobMetrics* metrics() const override { return &metrics_; }

 private:
  struct Worker {
    std::string id;
    ChildProcess process;
    std::string stage;  // the stage last seen in progress.json, and since when
    std::chrono::steady_clock::time_point stage_since;
  };
  void finish(Worker& w, const ChildEnd& end);
  void follow_stage(Worker& w, const std::string& stage, bool job_finished);
  int requeue_adopted();  // store_.adopt(), each back to the queue
  void follow_workers();
  std::string folder(const std::string& id) const;

  JobStore& store_;
  LocalExecutorOptions options_;
  mutable std::mutex mutex_;
  std::map<std::string, std::unique_ptr<Worker>> workers_;
  bool draining_ = false;
  std::chrono::steady_clock::time_point last_adopt_{};
  JobMetrics metrics_;
};

}  // namespace lorgnette::service
