// The job store: every capture and the state of its job, owned by the server (its only writer).
// An interface so that SQLite (the embedded default, sqlite_store.h) and PostgreSQL (deployments
// with several hosts; not written yet) serve the same server through the same schema
// (schema.h: one list of migrations, applied in order, its version recorded in the database).
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
};

class JobStore {
 public:
  virtual ~JobStore() = default;
  virtual int schema_version() = 0;
  // Throws when the id exists.
  virtual void insert(const CaptureRecord& r) = 0;
  virtual std::optional<CaptureRecord> get(const std::string& id) = 0;
  // Replaces the row with r.id (and sets updated_unix); returns false when there is none.
  virtual bool update(const CaptureRecord& r) = 0;
  virtual bool remove(const std::string& id) = 0;
  virtual std::vector<CaptureRecord> with_state(JobState s) = 0;  // oldest queued first
  virtual std::vector<std::string> created_before(int64_t unix_seconds) = 0;
  virtual std::map<JobState, int64_t> count_by_state() = 0;
  // The oldest queued job, moved to running with one more attempt in one transaction (so two
  // servers on one database never take the same job); nothing when the queue is empty.
  virtual std::optional<CaptureRecord> claim_next() = 0;
};

int64_t unix_now();

}  // namespace lorgnette::service
