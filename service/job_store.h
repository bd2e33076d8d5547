// The job store: every capture and the state of its job, owned by the server (its only writer).
// An interface so that SQLite (the embedded default, sqlite_store.h) and PostgreSQL (deployments
// with several hosts) serve the same server through the same schema (schema.h: one list of
// migrations, applied in order, its version recorded in the database).
//
// Several servers may share one database. A running job belongs to the server that claimed it
// (its owner: a random id per server process start, with the host) for as long as that server
// renews the job's lease: a heartbeat timestamp taken from the database's clock (so the servers'
// own clocks never matter). A row whose lease has expired, or one left by an earlier process of
// the same server (the same home: an identity kept in the data folder, server_identity.h), is
// adopted by another server, which hands it back to the queue or re-attaches its worker.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace lorgnette::service {

// created: waiting for its upload; queued: uploaded and started, waiting for a worker slot;
// running: a worker has it; failed / finished: its worker ended (failed: the product's message).
enum class JobState { Created, Queued, Running, Failed, Finished };
const char* to_string(JobState s);
JobState job_state_from_string(const std::string& s);  // throws on an unknown name

struct CaptureRecord {
  std::string id;          // random, 128 bits (tokens.h): not enumerable
  std::string token_hash;  // SHA-256 of the capture's secret token, hex; the token itself is never stored
  JobState state = JobState::Created;
  std::string stage, message;  // the worker's last report (progress.h)
  double percent = 0.0;
  int attempts = 0;         // worker starts, including retries after a worker was killed
  std::string upload_kind;  // "" (nothing yet), "video" or "images"
  int64_t created_unix = 0, updated_unix = 0, queued_unix = 0;
  std::string executor_job_id;  // the worker's id in an external scheduler (Slurm); "" = none
  std::string owner;            // the server process running it (JobOwner::instance); "" = none yet
  std::string owner_home;       // that server's home (JobOwner::home)
  int64_t heartbeat_ms = 0;     // the lease's last renewal, the database's clock (Unix-epoch ms)
};

// Who claims and renews jobs: one server process.
struct JobOwner {
  std::string instance;  // random per process start, with the host: "<16 hex>@<host>"
  std::string home;      // persisted in the data folder, with the host; shared by the server's restarts
};

class JobStore {
 public:
  virtual ~JobStore() = default;
  virtual int schema_version() = 0;
  // Throws when the id exists.
  virtual void insert(const CaptureRecord& r) = 0;
  virtual std::optional<CaptureRecord> get(const std::string& id) = 0;
  // Replaces the row with r.id (and sets updated_unix; the heartbeat is kept); returns false when
  // there is none.
  virtual bool update(const CaptureRecord& r) = 0;
  // The same, only while the row's owner is `owner`: a server never overwrites a job another
  // server has adopted since (returns false then).
  virtual bool update_owned(const CaptureRecord& r, const std::string& owner) = 0;
  virtual bool remove(const std::string& id) = 0;
  virtual std::vector<CaptureRecord> with_state(JobState s) = 0;  // oldest queued first
  virtual std::vector<std::string> created_before(int64_t unix_seconds) = 0;
  virtual std::map<JobState, int64_t> count_by_state() = 0;
  // The oldest queued job, moved to running with one more attempt, owned by `by` with a fresh
  // lease, in one transaction (so two servers on one database never take the same job); nothing
  // when the queue is empty.
  virtual std::optional<CaptureRecord> claim_next(const JobOwner& by) = 0;
  // Renews the lease of every running job `owner` holds; returns how many.
  virtual int renew_leases(const std::string& owner) = 0;
  // Takes over, in one transaction, the running jobs whose lease is older than `lease_ms` and those
  // of an earlier process of by's home (a restart), so that each is adopted by one server only; returns
  // them as they are now (owned by `by`, lease renewed).
  virtual std::vector<CaptureRecord> adopt(const JobOwner& by, int64_t lease_ms) = 0;
};

int64_t unix_now();

}  // namespace lorgnette::service
