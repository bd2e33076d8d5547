// The Slurm executor: each job is one batch job running `lorgnette job run <capture folder>` on
// the farm, the data folder being the filesystem the farm shares. Submitted with `sbatch
// --parsable --requeue` (so Slurm itself requeues it when its node fails), named lgn-<capture id>,
// its output appended to the folder's worker.log; followed with `squeue --states=all` and, when it
// ends, `scontrol show job` for its exit code; cancelled with `scancel`. Every command runs through
// fork/execv with argv (command.h); the only script is the one-line batch script the executor writes
// itself from the operator's settings and the capture folder's path.
//
// The Slurm job id is stored with the job (CaptureRecord::executor_job_id), so a server killed and
// restarted re-attaches running jobs instead of starting them twice; a graceful shutdown leaves
// them running on the farm for the next server to re-attach. With several servers on one database
// a server follows only the jobs it owns (job_store.h); it adopts, and re-attaches by the same id,
// those of its own earlier process at start and those whose lease expired at any time. A job's end means, as
// for the local executor: progress.json "finished" -> finished; "failed" -> failed with the product's
// message; anything else (cancelled by an operator, a node failure Slurm did not requeue, a time limit, exit
// 75 after SIGTERM) -> queued again while attempts remain; a crash (a signal other than
// SIGKILL/SIGTERM/SIGINT) -> failed, saying so.
#pragma once
#include <chrono>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "service/executor.h"
#include "service/job_store.h"
#include "service/progress.h"

namespace lorgnette::service {

struct SlurmExecutorOptions {
  int max_attempts = 3;                   // submissions per job before a killed job fails
  std::string data_dir;                   // capture folders are data_dir/captures/<id> (shared)
  std::string worker_exe;                 // the lorgnette binary on the nodes ("" = this executable)
  std::vector<std::string> global_flags;  // passed before `job run` (e.g. --kernel-cache DIR)
  std::string partition;                  // "" = the cluster's default
  std::string gres;                       // e.g. "gpu:1"; "" = none
  std::vector<std::string> sbatch_args;   // extra `--name=value` options (validated)
  std::string bin_dir;                    // folder of sbatch/squeue/scontrol/scancel ("" = $PATH)
  double poll_seconds = 2.0;              // how often squeue is asked
  LeaseSettings lease;                    // who this server is, and its jobs' lease
};

// Throws with what is wrong when an option could reach sbatch as something else than intended
// (a partition or gres with unexpected characters, an extra argument that is not `--name[=value]`
// or that sets what the executor owns: output, job name, requeue, working folder, script).
void validate_slurm_options(const SlurmExecutorOptions& o);

class SlurmExecutor final : public Executor {
 public:
  // Throws when the options are invalid or a Slurm client program is missing.
  SlurmExecutor(JobStore& store, SlurmExecutorOptions options);

  int reconcile() override;
  void tick() override;
  void cancel(const std::string& id) override;
  void interrupt_all() override;
  int running() const override;
  std::string slurm_job_id(const std::string& id) const;  // "" when not followed
  // Stage seconds from each finished job's own progress.json (its worker's clock, so a job run
  // while no server followed it is measured too) and failures by cause (job_metrics.h).
  const JobMetrics* metrics() const override { return &metrics_; }

 private:
  bool submit(CaptureRecord job);  // false when sbatch failed (the job queued again or failed)
  std::optional<std::map<std::string, std::string>> poll_states();  // Slurm id -> state
  std::string active_job_named(const std::string& name) const;      // its Slurm id, or ""
  void finish(const std::string& id, const std::string& slurm_id, const std::string& slurm_state);
  bool take_over(CaptureRecord r);  // an adopted job: re-attached (true) or back to the queue
  int take_over_adopted();          // store_.adopt(), each taken over; returns how many
  void follow_jobs();               // squeue, finished jobs recorded, progress copied
  void record_metrics(const Progress& p);
  std::string folder(const std::string& id) const;
  std::string program(const char* name) const;

  JobStore& store_;
  SlurmExecutorOptions options_;
  mutable std::mutex mutex_;
  std::map<std::string, std::string> jobs_;  // capture id -> Slurm job id
  std::chrono::steady_clock::time_point last_poll_{}, submit_pause_until_{};
  bool draining_ = false;
  std::chrono::steady_clock::time_point last_adopt_{};
  JobMetrics metrics_;
};

}  // namespace lorgnette::service
