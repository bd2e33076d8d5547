// PostgreSQL implementation of JobStore (postgres_store.h). Every query is parameterised
// (PQexecParams, text values), so no value is ever spliced into SQL.
#include "service/postgres_store.h"

#include <fmt/format.h>
#include <libpq-fe.h>

#include <mutex>
#include <stdexcept>

#include "service/schema.h"

namespace lorgnette::service {
namespace {

struct ConnFinish {
  void operator()(PGconn* c) const { PQfinish(c); }
};
struct ResultClear {
  void operator()(PGresult* r) const { PQclear(r); }
};
using Conn = std::unique_ptr<PGconn, ConnFinish>;
using Result = std::unique_ptr<PGresult, ResultClear>;

// Any constant shared by every Lorgnette server: the key of the advisory lock around migrations.
constexpr const char* kMigrationLock = "4237184301";

// The database's clock in Unix-epoch milliseconds (clock_timestamp: the moment of the call, not the
// transaction's start): every lease is stamped and compared by it.
constexpr const char* kPostgresNowMs = "(EXTRACT(EPOCH FROM clock_timestamp()) * 1000)::bigint";

std::string trimmed(const char* message) {
  std::string s = message ? message : "";
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

class PostgresStore final : public JobStore {
 public:
  explicit PostgresStore(const std::string& conninfo);
  int schema_version() override;
  void insert(const CaptureRecord& r) override;
  std::optional<CaptureRecord> get(const std::string& id) override;
  bool update(const CaptureRecord& r) override;
  bool update_owned(const CaptureRecord& r, const std::string& owner) override;
  bool remove(const std::string& id) override;
  std::vector<CaptureRecord> with_state(JobState s) override;
  std::vector<std::string> created_before(int64_t unix_seconds) override;
  std::map<JobState, int64_t> count_by_state() override;
  std::optional<CaptureRecord> claim_next(const JobOwner& by) override;
  int renew_leases(const std::string& owner) override;
  std::vector<CaptureRecord> adopt(const JobOwner& by, int64_t lease_ms) override;

 private:
  bool update_row(const CaptureRecord& r, const std::string* owner);
  Result exec(const std::string& sql, const std::vector<std::string>& params = {});
  int version_unlocked();
  void migrate();
  bool migrate_one_step();
  static std::vector<std::string> record_params(const CaptureRecord& r);
  static std::vector<CaptureRecord> rows(const PGresult* res);

  std::string description_;  // database, host and user: never the password
  Conn conn_;
  std::mutex mutex_;
};

PostgresStore::PostgresStore(const std::string& conninfo) : description_(describe_conninfo(conninfo)) {
  if (description_.front() == '(') throw std::runtime_error("job store: " + description_);
  conn_.reset(PQconnectdb(conninfo.c_str()));
  if (!conn_ || PQstatus(conn_.get()) != CONNECTION_OK)
    throw std::runtime_error(fmt::format(
        "job store {}: cannot connect (is the server running, and are the database and user there?): {}",
        description_, trimmed(conn_ ? PQerrorMessage(conn_.get()) : "out of memory")));
  exec("SET client_min_messages = warning");  // no NOTICE lines from CREATE ... IF NOT EXISTS
  migrate();
}

Result PostgresStore::exec(const std::string& sql, const std::vector<std::string>& params) {
  // A connection lost since the last call (a server restart) is opened again before sending
  // anything, so no statement is ever sent twice.
  if (PQstatus(conn_.get()) != CONNECTION_OK) PQreset(conn_.get());
  std::vector<const char*> values;
  for (const auto& p : params) values.push_back(p.c_str());
  Result res(PQexecParams(conn_.get(), sql.c_str(), int(values.size()), nullptr, values.data(), nullptr,
                          nullptr, 0));
  const ExecStatusType st = res ? PQresultStatus(res.get()) : PGRES_FATAL_ERROR;
  if (st != PGRES_COMMAND_OK && st != PGRES_TUPLES_OK)
    throw std::runtime_error(fmt::format("job store {}: {} failed: {}", description_, sql.substr(0, 60),
                                         trimmed(PQerrorMessage(conn_.get()))));
  return res;
}

int PostgresStore::version_unlocked() {
  exec(
      "CREATE TABLE IF NOT EXISTS schema_migrations (version INTEGER PRIMARY KEY, applied_unix BIGINT NOT "
      "NULL)");
  Result r = exec("SELECT COALESCE(MAX(version), 0) FROM schema_migrations");
  return std::stoi(PQgetvalue(r.get(), 0, 0));
}

// Applies the next missing migration in one transaction under the migration lock; returns false
// when none is missing. Another server starting at the same moment waits on the lock, then finds
// the migration recorded.
bool PostgresStore::migrate_one_step() {
  exec("BEGIN");
  try {
    exec("SELECT pg_advisory_xact_lock($1::bigint)", {kMigrationLock});
    const int have = version_unlocked();
    if (have > latest_schema_version())
      throw std::runtime_error(fmt::format(
          "job store {} has schema version {}, newer than this Lorgnette's {}: run the newer Lorgnette, or "
          "point --db at another database",
          description_, have, latest_schema_version()));
    const Migration* next = nullptr;
    for (const Migration& m : migrations())
      if (m.version > have) {
        next = &m;
        break;
      }
    if (next) {
      for (const auto& sql : next->statements) exec(sql);
      exec("INSERT INTO schema_migrations VALUES ($1, $2)",
           {std::to_string(next->version), std::to_string(unix_now())});
    }
    exec("COMMIT");
    return next != nullptr;
  } catch (...) {
    Result ignored(PQexec(conn_.get(), "ROLLBACK"));
    throw;
  }
}

void PostgresStore::migrate() {
  while (migrate_one_step()) {
  }
}

int PostgresStore::schema_version() {
  std::lock_guard<std::mutex> lock(mutex_);
  return version_unlocked();
}

std::vector<std::string> PostgresStore::record_params(const CaptureRecord& r) {
  return {r.id,
          r.token_hash,
          to_string(r.state),
          r.stage,
          r.message,
          fmt::format("{}", r.percent),  // shortest text that reads back as the same double
          std::to_string(r.attempts),
          r.upload_kind,
          std::to_string(r.created_unix),
          std::to_string(r.updated_unix),
          std::to_string(r.queued_unix),
          r.executor_job_id,
          r.owner,
          r.owner_home,
          std::to_string(r.heartbeat_ms)};
}

std::vector<CaptureRecord> PostgresStore::rows(const PGresult* res) {
  std::vector<CaptureRecord> out;
  for (int i = 0; i < PQntuples(res); ++i) {
    auto v = [&](int c) { return std::string(PQgetvalue(res, i, c)); };
    CaptureRecord r;
    r.id = v(0), r.token_hash = v(1), r.state = job_state_from_string(v(2));
    r.stage = v(3), r.message = v(4), r.percent = std::stod(v(5)), r.attempts = std::stoi(v(6));
    r.upload_kind = v(7), r.created_unix = std::stoll(v(8)), r.updated_unix = std::stoll(v(9));
    r.queued_unix = std::stoll(v(10)), r.executor_job_id = v(11);
    r.owner = v(12), r.owner_home = v(13), r.heartbeat_ms = std::stoll(v(14));
    out.push_back(std::move(r));
  }
  return out;
}

void PostgresStore::insert(const CaptureRecord& r) {
  std::lock_guard<std::mutex> lock(mutex_);
  exec(fmt::format("INSERT INTO captures ({}) VALUES ($1,$2,$3,$4,$5,$6,$7,$8,$9,$10,$11,$12,$13,$14,$15)",
                   kCaptureColumns),
       record_params(r));
}

std::optional<CaptureRecord> PostgresStore::get(const std::string& id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Result res = exec(fmt::format("SELECT {} FROM captures WHERE id = $1", kCaptureColumns), {id});
  auto r = rows(res.get());
  if (r.empty()) return std::nullopt;
  return r.front();
}

bool PostgresStore::update(const CaptureRecord& r) { return update_row(r, nullptr); }

bool PostgresStore::update_owned(const CaptureRecord& r, const std::string& owner) {
  return update_row(r, &owner);
}

// Every column but the heartbeat, which only claim_next, renew_leases and adopt set (by the
// database's clock); with `owner`, only while the row is still that server's.
bool PostgresStore::update_row(const CaptureRecord& r, const std::string* owner) {
  std::lock_guard<std::mutex> lock(mutex_);
  CaptureRecord copy = r;
  copy.updated_unix = unix_now();
  std::vector<std::string> params = record_params(copy);
  params.pop_back();  // the heartbeat
  if (owner) params.push_back(*owner);
  Result res = exec(std::string("UPDATE captures SET token_hash = $2, state = $3, stage = $4, message = $5, "
                                "percent = $6, attempts = $7, upload_kind = $8, created_unix = $9, "
                                "updated_unix = $10, queued_unix = $11, executor_job_id = $12, owner = $13, "
                                "owner_home = $14 WHERE id = $1") +
                        (owner ? " AND owner = $15" : ""),
                    params);
  return std::string(PQcmdTuples(res.get())) != "0";
}

bool PostgresStore::remove(const std::string& id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Result res = exec("DELETE FROM captures WHERE id = $1", {id});
  return std::string(PQcmdTuples(res.get())) != "0";
}

std::vector<CaptureRecord> PostgresStore::with_state(JobState s) {
  std::lock_guard<std::mutex> lock(mutex_);
  Result res =
      exec(fmt::format("SELECT {} FROM captures WHERE state = $1 ORDER BY queued_unix, created_unix, id",
                       kCaptureColumns),
           {to_string(s)});
  return rows(res.get());
}

std::vector<std::string> PostgresStore::created_before(int64_t unix_seconds) {
  std::lock_guard<std::mutex> lock(mutex_);
  Result res = exec("SELECT id FROM captures WHERE created_unix < $1 ORDER BY created_unix",
                    {std::to_string(unix_seconds)});
  std::vector<std::string> ids;
  for (int i = 0; i < PQntuples(res.get()); ++i) ids.emplace_back(PQgetvalue(res.get(), i, 0));
  return ids;
}

std::map<JobState, int64_t> PostgresStore::count_by_state() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::map<JobState, int64_t> counts;
  for (JobState s :
       {JobState::Created, JobState::Queued, JobState::Running, JobState::Failed, JobState::Finished})
    counts[s] = 0;
  Result res = exec("SELECT state, COUNT(*) FROM captures GROUP BY state");
  for (int i = 0; i < PQntuples(res.get()); ++i)
    counts[job_state_from_string(PQgetvalue(res.get(), i, 0))] = std::stoll(PQgetvalue(res.get(), i, 1));
  return counts;
}

std::optional<CaptureRecord> PostgresStore::claim_next(const JobOwner& by) {
  std::lock_guard<std::mutex> lock(mutex_);
  // One statement, so one transaction: the row is locked by the inner SELECT and updated before any
  // other connection can see it queued; SKIP LOCKED lets a second server take the next row instead of
  // waiting for this one (and then finding it no longer queued).
  Result res =
      exec(fmt::format("UPDATE captures SET state = 'running', attempts = attempts + 1, "
                       "updated_unix = $1, owner = $2, owner_home = $3, heartbeat_ms = {} WHERE id = "
                       "(SELECT id FROM captures WHERE state = 'queued' ORDER BY queued_unix, "
                       "created_unix, id LIMIT 1 FOR UPDATE SKIP LOCKED) RETURNING {}",
                       kPostgresNowMs, kCaptureColumns),
           {std::to_string(unix_now()), by.instance, by.home});
  auto r = rows(res.get());
  if (r.empty()) return std::nullopt;
  return r.front();
}

int PostgresStore::renew_leases(const std::string& owner) {
  std::lock_guard<std::mutex> lock(mutex_);
  Result res =
      exec(fmt::format("UPDATE captures SET heartbeat_ms = {} WHERE state = 'running' AND owner = $1",
                       kPostgresNowMs),
           {owner});
  return std::stoi(PQcmdTuples(res.get()));
}

// One statement: a second server adopting at the same moment waits for the row lock, then reads
// the row again (READ COMMITTED) and finds its lease renewed by this one, so it leaves it.
std::vector<CaptureRecord> PostgresStore::adopt(const JobOwner& by, int64_t lease_ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  Result res = exec(fmt::format("UPDATE captures SET owner = $1, owner_home = $2, heartbeat_ms = {0} WHERE "
                                "state = 'running' AND owner <> $1 AND (owner_home = $2 OR heartbeat_ms < "
                                "{0} - $3::bigint) RETURNING {1}",
                                kPostgresNowMs, kCaptureColumns),
                    {by.instance, by.home, std::to_string(lease_ms)});
  return rows(res.get());
}

}  // namespace

std::string describe_conninfo(const std::string& conninfo) {
  char* err = nullptr;
  PQconninfoOption* opts = PQconninfoParse(conninfo.c_str(), &err);
  if (!opts) {
    // libpq's message may quote the faulty part, which can be the password: not shown.
    PQfreemem(err);
    return "(an unreadable PostgreSQL connection string: write it as postgresql://user@host:port/dbname "
           "or 'host=... dbname=...')";
  }
  std::string db, host, port, user;
  for (PQconninfoOption* o = opts; o->keyword; ++o) {
    if (!o->val) continue;
    const std::string k = o->keyword;
    if (k == "dbname") db = o->val;
    if (k == "host" || (k == "hostaddr" && host.empty())) host = o->val;
    if (k == "port") port = o->val;
    if (k == "user") user = o->val;
  }
  PQconninfoFree(opts);
  return fmt::format("postgresql database '{}' on '{}{}'{}", db.empty() ? "(the user's)" : db,
                     host.empty() ? "(the default socket)" : host, port.empty() ? "" : ":" + port,
                     user.empty() ? "" : " as '" + user + "'");
}

std::unique_ptr<JobStore> open_postgres_store(const std::string& conninfo) {
  return std::make_unique<PostgresStore>(conninfo);
}

}  // namespace lorgnette::service
