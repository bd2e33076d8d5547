// Where jobs run, as the server sees it: an executor takes queued jobs from the job store, starts
// each as `lorgnette job run <capture folder>` somewhere (a child process: local_executor.h; a Slurm
// batch job: slurm_executor.h), records the worker's progress.json into the store (the server stays
// the only writer of job state) and decides what a worker's end means for its job.
#pragma once
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>

#include "service/job_metrics.h"
#include "service/job_store.h"
#include "service/server_identity.h"

namespace lorgnette::service {

// How a server holds its running jobs when several share one database (job_store.h). The lease
// is 60 s by default and renewed every sixth of it (10 s, LeaseKeeper), so a job changes hands only
// after five renewals in a row were missed: a live server is not robbed by a database restart or
// failover, or a slow disk, of up to about 50 s, while a crashed server's jobs wait about a minute
// before another server takes them over (short against a job's minutes of training; a restart of
// the same server takes its own back at once, by its home). Even a job taken from a server that
// was only cut off is never run twice at once: its folder's job.lock keeps the second worker
// waiting until the first has ended, and the second then skips the stages done.
struct LeaseSettings {
  JobOwner owner = ephemeral_owner();
  double lease_seconds = 60.0;
  int64_t lease_ms() const { return int64_t(lease_seconds * 1000.0); }
  // How often leases are renewed and expired ones looked for.
  std::chrono::duration<double> check_every() const {
    return std::chrono::duration<double>(lease_seconds / 6.0);
  }
};

// The worker's progress.json in its capture folder into the record (stage, percent, message), as
// both executors report it; a folder without one leaves the record as it was.
void refresh_progress(CaptureRecord& r, const std::filesystem::path& capture_folder);

// A worker ended by SIGKILL, SIGTERM or SIGINT was stopped (an operator, a shutdown, the OOM killer,
// Slurm's preemption), not crashed: both executors retry its job.
bool retryable_signal(int sig);

class Executor {
 public:
  virtual ~Executor() = default;
  // At server start: running jobs left by an earlier process of this server (its home) or whose
  // lease has expired are adopted and either re-attached (their worker still runs elsewhere) or
  // handed back to the queue; returns how many. tick() does the same for expired leases.
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
