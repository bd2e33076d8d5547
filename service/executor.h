// Where jobs run, as the server sees it: an executor takes queued jobs from the job store, starts
// each as `lorgnette job run <capture folder>` somewhere (a child process: local_executor.h; a Slurm
// batch job: slurm_executor.h), records the worker's progress.json into the store (the server stays
// the only writer of job state) and decides what a worker's end means for its job.
#pragma once
#include <string>

#include "service/job_metrics.h"

namespace lorgnette::service {

class Executor {
 public:
  virtual ~Executor() = default;
  // At server start: jobs the store says are running, left by a previous server, are either
  // re-attached (their worker still runs elsewhere) or handed back to the queue; returns how many.
  virtual int reconcile() = 0;
  // One pass: record ended workers and the progress of running ones, then start queued jobs. The
  // server calls it from one loop several times a second; thread-safe with cancel().
  virtual void tick() = 0;
  // Stops the worker of `id` if it has one (a deleted capture) and forgets it.
  virtual void cancel(const std::string& id) = 0;
  // The server is shutting down: start nothing new, and let go of running workers (stopped and
  // handed back to the queue, or left running to be re-attached by the next server).
  virtual void interrupt_all() = 0;
  virtual int running() const = 0;  // workers this server follows now
  // Stage seconds and failures by cause for /metrics (job_metrics.h); nullptr where the executor
  // does not measure them.
  virtual const JobMetrics* metrics() const { return nullptr; }
};

}  // namespace lorgnette::service
