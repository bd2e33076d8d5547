// Jobs as Slurm batch jobs (slurm_executor.h).
#include "service/slurm_executor.h"

#include <fmt/format.h>
#include <signal.h>
#include <spdlog/spdlog.h>
#include <string.h>

#include <filesystem>
#include <regex>
#include <set>
#include <sstream>

#include "host/util/image_io.h"
#include "service/child_process.h"
#include "service/command.h"
#include "service/progress.h"

namespace fs = std::filesystem;

namespace lorgnette::service {
namespace {

constexpr double kCommandSeconds = 30.0;  // a controller slower than this is treated as down

// Options the executor sets itself: the job's identity, output, folder and requeue behaviour.
const std::set<std::string> kOwnedOptions = {"output",    "error",     "input",   "job-name",   "parsable",
                                             "wrap",      "chdir",     "requeue", "no-requeue", "open-mode",
                                             "test-only", "partition", "gres",    "array"};

// States in which a Slurm job may still run (or run again: requeued, held by an operator).
bool active(const std::string& state) {
  static const std::set<std::string> states = {
      "PENDING",      "CONFIGURING",   "RUNNING",  "COMPLETING", "SUSPENDED", "REQUEUED", "REQUEUE_FED",
      "REQUEUE_HOLD", "RESV_DEL_HOLD", "RESIZING", "SIGNALING",  "STAGE_OUT", "STOPPED"};
  return states.count(state) > 0;
}

// Single-quoted for sh: the batch script is the only text a shell reads, and every word in it is
// quoted, so a path with spaces or quotes stays one argument.
std::string sh_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string first_line(const std::string& s) {
  std::string t = s.substr(0, s.find('\n'));
  return t.empty() ? "(no message)" : t;
}

struct SlurmExit {
  int code = 0, signal = 0;
};

// "ExitCode=<code>:<signal>" from `scontrol show job -o`; nothing once Slurm has forgotten the job.
std::optional<SlurmExit> parse_exit_code(const std::string& scontrol_out) {
  static const std::regex re("(?:^|\\s)ExitCode=(\\d+):(\\d+)");
  std::smatch m;
  if (!std::regex_search(scontrol_out, m, re)) return std::nullopt;
  return SlurmExit{std::stoi(m[1]), std::stoi(m[2])};
}

}  // namespace

void validate_slurm_options(const SlurmExecutorOptions& o) {
  static const std::regex partition("[A-Za-z0-9_.,-]*"), gres("[A-Za-z0-9_.,:/-]*"),
      arg("--([a-z][a-z0-9-]*)(=[^\\n\\r]*)?");
  if (!std::regex_match(o.partition, partition))
    throw std::invalid_argument(fmt::format(
        "--slurm-partition '{}' has characters a partition name cannot have (letters, digits, _ . , -)",
        o.partition));
  if (!std::regex_match(o.gres, gres))
    throw std::invalid_argument(fmt::format(
        "--slurm-gres '{}' is not a gres list like 'gpu:1' or 'gpu:h200:2' (letters, digits, _ . , : / -)",
        o.gres));
  for (const std::string& a : o.sbatch_args) {
    std::smatch m;
    if (!std::regex_match(a, m, arg))
      throw std::invalid_argument(
          fmt::format("--slurm-arg '{}' is not one sbatch option of the form --name or --name=value (e.g. "
                      "--time=02:00:00)",
                      a));
    if (kOwnedOptions.count(m[1]))
      throw std::invalid_argument(fmt::format(
          "--slurm-arg '{}' sets what the executor sets itself (or has its own flag: --slurm-partition, "
          "--slurm-gres); leave it out",
          a));
  }
  if (o.data_dir.find_first_of("%\\\n") != std::string::npos)
    throw std::invalid_argument(fmt::format(
        "the data folder '{}' has a '%', '\\' or newline, which sbatch's --output would read as a pattern: "
        "use a folder without them",
        o.data_dir));
  if (o.max_attempts < 1 || !(o.poll_seconds > 0.0))
    throw std::invalid_argument("the Slurm executor needs max_attempts >= 1 and poll_seconds > 0");
}

SlurmExecutor::SlurmExecutor(JobStore& store, SlurmExecutorOptions options)
    : store_(store), options_(std::move(options)) {
  validate_slurm_options(options_);
  if (options_.worker_exe.empty()) options_.worker_exe = self_executable();
  for (const char* p : {"sbatch", "squeue", "scontrol", "scancel"})
    if (find_program(p, options_.bin_dir).empty())
      throw std::runtime_error(
          fmt::format("the Slurm executor needs '{}' (Debian package slurm-client) in {}: install it or pass "
                      "--slurm-bin-dir",
                      p, options_.bin_dir.empty() ? "$PATH" : "'" + options_.bin_dir + "'"));
}

std::string SlurmExecutor::program(const char* name) const { return find_program(name, options_.bin_dir); }

std::string SlurmExecutor::folder(const std::string& id) const {
  return (fs::path(options_.data_dir) / "captures" / id).string();
}

std::string SlurmExecutor::active_job_named(const std::string& name) const {
  const CommandResult r = run_command(
      {program("squeue"), "--noheader", "--me", "--states=all", "--name=" + name, "--format=%i|%T"},
      kCommandSeconds);
  std::istringstream in(r.out);
  for (std::string line; std::getline(in, line);) {
    const size_t bar = line.find('|');
    if (bar != std::string::npos && active(line.substr(bar + 1))) return line.substr(0, bar);
  }
  return "";
}

bool SlurmExecutor::take_over(CaptureRecord r) {
  const std::string& me = options_.lease.owner.instance;
  if (r.executor_job_id.empty()) {
    // The old server may have died between sbatch and recording the id: find the job by name.
    r.executor_job_id = active_job_named("lgn-" + r.id);
    if (!r.executor_job_id.empty()) store_.update_owned(r, me);
  }
  if (!r.executor_job_id.empty()) {
    jobs_[r.id] = r.executor_job_id;  // the next poll learns whether it still runs
    return true;
  }
  r.state = JobState::Queued;  // claimed but never submitted: the old server died in between
  r.message = "handed back to the queue: the server that claimed it stopped before submitting it";
  r.queued_unix = unix_now();
  store_.update_owned(r, me);
  return false;
}

int SlurmExecutor::take_over_adopted() {
  int attached = 0, requeued = 0;
  for (CaptureRecord& r : store_.adopt(options_.lease.owner, options_.lease.lease_ms()))
    ++(take_over(r) ? attached : requeued);
  last_poll_ = {};
  if (attached + requeued)
    spdlog::info("re-attached {} Slurm job(s); {} never submitted job(s) back to the queue", attached,
                 requeued);
  return attached + requeued;
}

int SlurmExecutor::reconcile() {
  std::lock_guard<std::mutex> lock(mutex_);
  last_adopt_ = std::chrono::steady_clock::now();
  return take_over_adopted();
}

bool SlurmExecutor::submit(CaptureRecord job) {
  static const std::regex safe_id("[A-Za-z0-9_-]+"), slurm_id("\\d+");
  const fs::path dir = folder(job.id);
  std::string error;
  if (!std::regex_match(job.id, safe_id)) {
    error = "the capture id has characters a job name cannot have";
  } else {
    std::string script =
        "#!/bin/sh\n# One Lorgnette job (written by `lorgnette serve`, Slurm executor).\nexec";
    script += " " + sh_quote(options_.worker_exe);
    for (const auto& f : options_.global_flags) script += " " + sh_quote(f);
    script += " job run " + sh_quote(dir.string()) + "\n";
    write_text_file_atomic((dir / "slurm-job.sh").string(), script);
    std::vector<std::string> argv{program("sbatch"),
                                  "--parsable",
                                  "--requeue",
                                  "--job-name=lgn-" + job.id,
                                  "--output=" + (dir / "worker.log").string(),
                                  "--open-mode=append",
                                  "--chdir=" + dir.string()};
    if (!options_.partition.empty()) argv.push_back("--partition=" + options_.partition);
    if (!options_.gres.empty()) argv.push_back("--gres=" + options_.gres);
    argv.insert(argv.end(), options_.sbatch_args.begin(), options_.sbatch_args.end());
    argv.push_back((dir / "slurm-job.sh").string());
    const CommandResult r = run_command(argv, kCommandSeconds);
    std::string id = first_line(r.out);
    id = id.substr(0, id.find(';'));  // "<id>[;<cluster>]"
    if (r.ok() && std::regex_match(id, slurm_id)) {
      job.executor_job_id = id;
      job.message = "waiting in the Slurm queue (job " + id + ")";
      store_.update_owned(job, options_.lease.owner.instance);
      jobs_[job.id] = id;
      spdlog::info("job {}: submitted to Slurm as job {}", job.id, id);
      return true;
    }
    error = "sbatch failed: " + first_line(r.err.empty() ? r.out : r.err);
  }
  const bool retry = job.attempts < options_.max_attempts;
  job.state = retry ? JobState::Queued : JobState::Failed;
  job.message =
      retry ? fmt::format("{}; retrying (attempt {} of {})", error, job.attempts + 1, options_.max_attempts)
            : error;
  if (retry) job.queued_unix = unix_now();
  if (!retry) metrics_.count_failure("", "start");
  store_.update_owned(job, options_.lease.owner.instance);
  spdlog::error("job {}: {}", job.id, error);
  return false;
}

std::optional<std::map<std::string, std::string>> SlurmExecutor::poll_states() {
  const CommandResult r = run_command(
      {program("squeue"), "--noheader", "--me", "--states=all", "--format=%i|%T"}, kCommandSeconds);
  if (!r.ok()) {
    spdlog::warn("squeue failed ({}); the Slurm jobs' states are asked again in {} s", first_line(r.err),
                 options_.poll_seconds);
    return std::nullopt;
  }
  std::map<std::string, std::string> states;
  std::istringstream in(r.out);
  for (std::string line; std::getline(in, line);) {
    const size_t bar = line.find('|');
    if (bar != std::string::npos) states[line.substr(0, bar)] = line.substr(bar + 1);
  }
  return states;
}

void SlurmExecutor::record_metrics(const Progress& p) {
  for (const auto& [stage, seconds] : p.stage_seconds.items())
    if (seconds.is_number()) metrics_.observe_stage(stage, seconds.get<double>());
}

// `slurm_state` is the job's last state in squeue, or "gone" when Slurm no longer lists it.
void SlurmExecutor::finish(const std::string& id, const std::string& slurm_id,
                           const std::string& slurm_state) {
  auto rec = store_.get(id);
  if (!rec) return;  // deleted meanwhile
  CaptureRecord r = *rec;
  refresh_progress(r, folder(r.id));
  const auto p = read_progress(fs::path(folder(id)) / "progress.json");
  std::string cause;
  if (p && p->state == "finished") {
    r.state = JobState::Finished;
  } else if (p && p->state == "failed") {
    r.state = JobState::Failed;  // the message is the product's, from progress.json
    cause = "refused";
  } else {
    const auto exit = parse_exit_code(
        run_command({program("scontrol"), "show", "job", "-o", slurm_id}, kCommandSeconds).out);
    const bool crashed = exit && exit->signal != 0 && !retryable_signal(exit->signal);
    const std::string during = r.stage.empty() ? "its start" : r.stage;
    if (!crashed && r.attempts < options_.max_attempts) {
      r.state = JobState::Queued;
      r.queued_unix = unix_now();
      r.message = fmt::format("the Slurm job {} ended ({}) during {}; retrying (attempt {} of {})", slurm_id,
                              slurm_state, during, r.attempts + 1, options_.max_attempts);
    } else {
      r.state = JobState::Failed;
      cause = crashed ? "crashed" : "killed";
      r.message = crashed ? fmt::format("the worker crashed ({}) during {} (Slurm job {})",
                                        strsignal(exit->signal), during, slurm_id)
                          : fmt::format("the Slurm job {} ended ({}) during {} after {} attempt(s)", slurm_id,
                                        slurm_state, during, r.attempts);
    }
  }
  if (!store_.update_owned(r, options_.lease.owner.instance)) return;  // another server's now
  if (p && (p->state == "finished" || p->state == "failed")) record_metrics(*p);
  if (!cause.empty()) metrics_.count_failure(r.stage, cause);
  spdlog::info("job {}: Slurm job {} ended ({}), now {}", id, slurm_id, slurm_state, to_string(r.state));
}

void SlurmExecutor::follow_jobs() {
  const auto now = std::chrono::steady_clock::now();
  if (!jobs_.empty() && now - last_poll_ >= std::chrono::duration<double>(options_.poll_seconds)) {
    last_poll_ = now;
    if (auto states = poll_states()) {
      for (auto it = jobs_.begin(); it != jobs_.end();) {
        const auto s = states->find(it->second);
        if (s != states->end() && active(s->second)) {
          ++it;
          continue;
        }
        finish(it->first, it->second, s == states->end() ? "gone" : s->second);
        it = jobs_.erase(it);
      }
    }
  }
  for (auto it = jobs_.begin(); it != jobs_.end();) {
    auto rec = store_.get(it->first);
    if (rec && rec->owner != options_.lease.owner.instance) {
      // Adopted by another server (this one's lease ran out): that server follows it now.
      spdlog::warn("job {}: another server has taken the Slurm job {} over", it->first, it->second);
      it = jobs_.erase(it);
      continue;
    }
    if (rec) {
      CaptureRecord r = *rec;
      refresh_progress(r, folder(r.id));
      if (r.stage != rec->stage || r.percent != rec->percent || r.message != rec->message)
        store_.update_owned(r, options_.lease.owner.instance);
    }
    ++it;
  }
}

void SlurmExecutor::tick() {
  std::lock_guard<std::mutex> lock(mutex_);
  follow_jobs();
  const auto now = std::chrono::steady_clock::now();
  if (now - last_adopt_ >= options_.lease.check_every()) {
    last_adopt_ = now;
    take_over_adopted();
  }
  if (draining_ || now < submit_pause_until_) return;
  while (auto job = store_.claim_next(options_.lease.owner)) {
    if (!submit(*job)) {
      submit_pause_until_ = now + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                      std::chrono::duration<double>(options_.poll_seconds));
      break;
    }
  }
}

void SlurmExecutor::cancel(const std::string& id) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::string slurm_id;
  if (auto it = jobs_.find(id); it != jobs_.end()) {
    slurm_id = it->second;
    jobs_.erase(it);
  } else if (auto rec = store_.get(id); rec && rec->state == JobState::Running) {
    slurm_id = rec->executor_job_id;
  }
  if (slurm_id.empty()) return;
  const CommandResult r = run_command({program("scancel"), slurm_id}, kCommandSeconds);
  if (!r.ok())
    spdlog::warn("job {}: scancel {} failed: {}", id, slurm_id, first_line(r.err));
  else
    spdlog::info("job {}: Slurm job {} cancelled", id, slurm_id);
}

void SlurmExecutor::interrupt_all() {
  std::lock_guard<std::mutex> lock(mutex_);
  draining_ = true;
  if (!jobs_.empty())
    spdlog::info("{} Slurm job(s) keep running on the cluster; the next server start re-attaches them",
                 jobs_.size());
  jobs_.clear();  // still "running" in the store, with their Slurm ids, for reconcile()
}

int SlurmExecutor::running() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return int(jobs_.size());
}

std::string SlurmExecutor::slurm_job_id(const std::string& id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = jobs_.find(id);
  return it == jobs_.end() ? "" : it->second;
}

}  // namespace lorgnette::service
