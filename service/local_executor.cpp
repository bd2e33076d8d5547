// Worker slots as child processes (local_executor.h).
#include "service/local_executor.h"

#include <fmt/format.h>
#include <signal.h>
#include <spdlog/spdlog.h>
#include <string.h>

#include <filesystem>

#include "service/job_runner.h"

namespace fs = std::filesystem;

namespace lorgnette::service {

LocalExecutor::LocalExecutor(JobStore& store, LocalExecutorOptions options)
    : store_(store), options_(std::move(options)) {
  if (options_.slots < 1) throw std::runtime_error("the local executor needs at least one worker slot");
  if (options_.worker_exe.empty()) options_.worker_exe = self_executable();
}

LocalExecutor::~LocalExecutor() = default;

std::string LocalExecutor::folder(const std::string& id) const {
  return (fs::path(options_.data_dir) / "captures" / id).string();
}

int LocalExecutor::requeue_adopted() {
  int n = 0;
  for (CaptureRecord r : store_.adopt(options_.lease.owner, options_.lease.lease_ms())) {
    r.state = JobState::Queued;
    r.message = "handed back to the queue: the server that ran it stopped";
    r.queued_unix = unix_now();
    if (store_.update_owned(r, options_.lease.owner.instance)) ++n;
  }
  return n;
}

int LocalExecutor::reconcile() {
  std::lock_guard<std::mutex> lock(mutex_);
  last_adopt_ = std::chrono::steady_clock::now();
  const int n = requeue_adopted();
  if (n) spdlog::info("reconciled {} running job(s) back to the queue", n);
  return n;
}

// Records the stage that ended when a worker moved on from it (or finished the job with it).
void LocalExecutor::follow_stage(Worker& w, const std::string& stage, bool job_finished) {
  const auto now = std::chrono::steady_clock::now();
  if (!w.stage.empty() && (stage != w.stage || job_finished))
    metrics_.observe_stage(w.stage, std::chrono::duration<double>(now - w.stage_since).count());
  if (stage != w.stage) w.stage = stage, w.stage_since = now;
}

void LocalExecutor::finish(Worker& w, const ChildEnd& end) {
  auto rec = store_.get(w.id);
  if (!rec) return;  // deleted meanwhile
  CaptureRecord r = *rec;
  refresh_progress(r, folder(r.id));
  const bool finished = end.exited && end.code == int(JobOutcome::Finished);
  follow_stage(w, r.stage, finished);
  std::string cause;
  if (finished) {
    r.state = JobState::Finished;
  } else if (end.exited && end.code == int(JobOutcome::Failed)) {
    r.state = JobState::Failed;  // the message is the product's, from progress.json
    cause = "refused";
  } else if (end.exited && end.code == int(JobOutcome::Interrupted)) {
    r.state = JobState::Queued;
  } else if (!end.exited && retryable_signal(end.signal) && r.attempts < options_.max_attempts) {
    r.state = JobState::Queued;
    r.message =
        fmt::format("the worker was stopped (signal {}) during {}; retrying (attempt {} of {})", end.signal,
                    r.stage.empty() ? "its start" : r.stage, r.attempts + 1, options_.max_attempts);
  } else {
    r.state = JobState::Failed;
    cause = end.exited ? "exit_status" : retryable_signal(end.signal) ? "killed" : "crashed";
    r.message = end.exited ? fmt::format("the worker ended with status {} during {}", end.code, r.stage)
                           : fmt::format("the worker crashed ({}) during {} after {} attempt(s)",
                                         strsignal(end.signal), r.stage, r.attempts);
  }
  if (!cause.empty()) metrics_.count_failure(r.stage, cause);
  if (r.state == JobState::Queued) r.queued_unix = unix_now();
  if (!store_.update_owned(r, options_.lease.owner.instance)) {
    spdlog::warn(
        "job {}: worker ended, but another server has taken the job over (this server's lease "
        "expired); its result is left to that server",
        w.id);
    return;
  }
  spdlog::info("job {}: worker ended ({} {}), now {}", w.id, end.exited ? "status" : "signal",
               end.exited ? end.code : end.signal, to_string(r.state));
}

// Ended workers recorded, running ones' progress copied; a worker whose row is gone (its capture
// deleted through any server) is killed.
void LocalExecutor::follow_workers() {
  for (auto it = workers_.begin(); it != workers_.end();) {
    if (auto end = it->second->process.poll()) {
      finish(*it->second, *end);
      it = workers_.erase(it);
      continue;
    }
    auto rec = store_.get(it->first);
    if (!rec) {
      spdlog::info("job {}: its capture was deleted; stopping its worker", it->first);
      it = workers_.erase(it);  // ChildProcess kills and reaps
      continue;
    }
    CaptureRecord r = *rec;
    refresh_progress(r, folder(r.id));
    follow_stage(*it->second, r.stage, false);
    if (r.stage != rec->stage || r.percent != rec->percent || r.message != rec->message)
      store_.update_owned(r, options_.lease.owner.instance);
    ++it;
  }
}

void LocalExecutor::tick() {
  std::lock_guard<std::mutex> lock(mutex_);
  follow_workers();
  const auto now = std::chrono::steady_clock::now();
  if (now - last_adopt_ >= options_.lease.check_every()) {
    last_adopt_ = now;
    if (const int n = requeue_adopted())
      spdlog::info("{} running job(s) whose server stopped renewing their lease: back to the queue", n);
  }
  while (!draining_ && int(workers_.size()) < options_.slots) {
    auto job = store_.claim_next(options_.lease.owner);
    if (!job) break;
    std::vector<std::string> argv{options_.worker_exe};
    argv.insert(argv.end(), options_.global_flags.begin(), options_.global_flags.end());
    argv.insert(argv.end(), {"job", "run", folder(job->id)});
    try {
      auto w = std::make_unique<Worker>(
          Worker{job->id, ChildProcess(argv, (fs::path(folder(job->id)) / "worker.log").string()), "", {}});
      workers_[job->id] = std::move(w);
    } catch (const std::exception& e) {
      job->state = JobState::Failed;
      job->message = e.what();
      store_.update_owned(*job, options_.lease.owner.instance);
      metrics_.count_failure("", "start");
    }
  }
}

void LocalExecutor::cancel(const std::string& id) {
  std::lock_guard<std::mutex> lock(mutex_);
  workers_.erase(id);  // ChildProcess kills and reaps
}

void LocalExecutor::interrupt_all() {
  std::lock_guard<std::mutex> lock(mutex_);
  draining_ = true;
  for (auto& [id, w] : workers_) w->process.signal(SIGTERM);
}

int LocalExecutor::running() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return int(workers_.size());
}

pid_t LocalExecutor::worker_pid(const std::string& id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = workers_.find(id);
  return it == workers_.end() ? -1 : it->second->process.pid();
}

}  // namespace lorgnette::service
