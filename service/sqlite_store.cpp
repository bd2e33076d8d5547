// SQLite implementation of JobStore (sqlite_store.h).
#include "service/sqlite_store.h"

#include <fmt/format.h>
#include <sqlite3.h>

#include <chrono>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "service/schema.h"

namespace lorgnette::service {
namespace {

struct DbClose {
  void operator()(sqlite3* db) const { sqlite3_close_v2(db); }
};
struct StmtFinalize {
  void operator()(sqlite3_stmt* s) const { sqlite3_finalize(s); }
};
using Db = std::unique_ptr<sqlite3, DbClose>;
using Stmt = std::unique_ptr<sqlite3_stmt, StmtFinalize>;

// The database's clock in Unix-epoch milliseconds: every lease is stamped and compared by it.
constexpr const char* kSqliteNowMs = "CAST((julianday('now') - 2440587.5) * 86400000.0 AS INTEGER)";

class SqliteStore final : public JobStore {
 public:
  explicit SqliteStore(const std::string& path);
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
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(fmt::format("job store '{}': {}: {}", path_, what, sqlite3_errmsg(db_.get())));
  }
  void exec(const std::string& sql);
  void set_wal_mode();
  Stmt prepare(const std::string& sql);
  int version_unlocked();
  void migrate();
  bool migrate_one_step();
  std::vector<CaptureRecord> rows(Stmt& st);
  void bind_record(sqlite3_stmt* st, const CaptureRecord& r, bool with_heartbeat);
  bool update_row(const CaptureRecord& r, const std::string* owner);
  std::vector<CaptureRecord> select_ids(const std::vector<std::string>& ids);
  template <class F>
  auto transaction(F&& work);

  std::string path_;
  Db db_;
  std::mutex mutex_;
};

std::string column_text(sqlite3_stmt* st, int i) {
  const unsigned char* t = sqlite3_column_text(st, i);
  return t ? reinterpret_cast<const char*>(t) : "";
}

SqliteStore::SqliteStore(const std::string& path) : path_(path) {
  sqlite3* raw = nullptr;
  const int rc = sqlite3_open_v2(path.c_str(), &raw,
                                 SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX, nullptr);
  db_.reset(raw);
  if (rc != SQLITE_OK) fail("cannot open (is its folder there and writable?)");
  sqlite3_busy_timeout(db_.get(), 5000);
  set_wal_mode();
  exec("PRAGMA foreign_keys=ON");
  migrate();
}

// Switching a new file to WAL takes an exclusive lock, and SQLite answers a second process doing the
// same at that moment with "database is locked" without calling the busy handler: so the switch is
// retried for as long as the busy timeout (5 s), like every other statement waits.
void SqliteStore::set_wal_mode() {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  for (;;) {
    const int rc = sqlite3_exec(db_.get(), "PRAGMA journal_mode=WAL", nullptr, nullptr, nullptr);
    const bool busy = rc == SQLITE_BUSY || rc == SQLITE_LOCKED;
    if (!busy || std::chrono::steady_clock::now() > until) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  exec("PRAGMA journal_mode=WAL");  // done already (a no-op), or its error with the message
}

void SqliteStore::exec(const std::string& sql) {
  char* err = nullptr;
  if (sqlite3_exec(db_.get(), sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
    std::string msg = err ? err : "";
    sqlite3_free(err);
    throw std::runtime_error(fmt::format("job store '{}': {} failed: {}", path_, sql.substr(0, 60), msg));
  }
}

Stmt SqliteStore::prepare(const std::string& sql) {
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db_.get(), sql.c_str(), -1, &st, nullptr) != SQLITE_OK)
    fail("cannot prepare " + sql);
  return Stmt(st);
}

int SqliteStore::version_unlocked() {
  exec(
      "CREATE TABLE IF NOT EXISTS schema_migrations (version INTEGER PRIMARY KEY, applied_unix BIGINT NOT "
      "NULL)");
  Stmt st = prepare("SELECT COALESCE(MAX(version), 0) FROM schema_migrations");
  if (sqlite3_step(st.get()) != SQLITE_ROW) fail("cannot read the schema version");
  return sqlite3_column_int(st.get(), 0);
}

// Applies the next missing migration in one write transaction; returns false when none is missing.
// The version is read inside the transaction, so a second process opening the same new file at
// the same moment waits for the write lock, then finds the migration recorded.
bool SqliteStore::migrate_one_step() {
  exec("BEGIN IMMEDIATE");
  try {
    const int have = version_unlocked();
    if (have > latest_schema_version())
      throw std::runtime_error(fmt::format(
          "job store '{}' has schema version {}, newer than this Lorgnette's {}: run the newer Lorgnette, or "
          "point --db at another file",
          path_, have, latest_schema_version()));
    const Migration* next = nullptr;
    for (const Migration& m : migrations())
      if (m.version > have) {
        next = &m;
        break;
      }
    if (next) {
      for (const auto& sql : next->statements) exec(sql);
      exec(fmt::format("INSERT INTO schema_migrations VALUES ({}, {})", next->version, unix_now()));
    }
    exec("COMMIT");
    return next != nullptr;
  } catch (...) {
    sqlite3_exec(db_.get(), "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

void SqliteStore::migrate() {
  while (migrate_one_step()) {
  }
}

int SqliteStore::schema_version() {
  std::lock_guard<std::mutex> lock(mutex_);
  return version_unlocked();
}

// Runs `work` inside BEGIN IMMEDIATE ... COMMIT (the write lock taken first, so no other process
// changes the rows it reads before it writes them), rolled back when it throws.
template <class F>
auto SqliteStore::transaction(F&& work) {
  exec("BEGIN IMMEDIATE");
  try {
    auto result = work();
    exec("COMMIT");
    return result;
  } catch (...) {
    sqlite3_exec(db_.get(), "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

void SqliteStore::bind_record(sqlite3_stmt* st, const CaptureRecord& r, bool with_heartbeat) {
  sqlite3_bind_text(st, 1, r.id.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(st, 2, r.token_hash.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(st, 3, to_string(r.state), -1, SQLITE_STATIC);
  sqlite3_bind_text(st, 4, r.stage.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(st, 5, r.message.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_double(st, 6, r.percent);
  sqlite3_bind_int(st, 7, r.attempts);
  sqlite3_bind_text(st, 8, r.upload_kind.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_int64(st, 9, r.created_unix);
  sqlite3_bind_int64(st, 10, r.updated_unix);
  sqlite3_bind_int64(st, 11, r.queued_unix);
  sqlite3_bind_text(st, 12, r.executor_job_id.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(st, 13, r.owner.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(st, 14, r.owner_home.c_str(), -1, SQLITE_TRANSIENT);
  if (with_heartbeat) sqlite3_bind_int64(st, 15, r.heartbeat_ms);
}

std::vector<CaptureRecord> SqliteStore::rows(Stmt& st) {
  std::vector<CaptureRecord> out;
  int rc;
  while ((rc = sqlite3_step(st.get())) == SQLITE_ROW) {
    CaptureRecord r;
    sqlite3_stmt* s = st.get();
    r.id = column_text(s, 0), r.token_hash = column_text(s, 1);
    r.state = job_state_from_string(column_text(s, 2));
    r.stage = column_text(s, 3), r.message = column_text(s, 4);
    r.percent = sqlite3_column_double(s, 5);
    r.attempts = sqlite3_column_int(s, 6);
    r.upload_kind = column_text(s, 7);
    r.created_unix = sqlite3_column_int64(s, 8), r.updated_unix = sqlite3_column_int64(s, 9);
    r.queued_unix = sqlite3_column_int64(s, 10);
    r.executor_job_id = column_text(s, 11);
    r.owner = column_text(s, 12), r.owner_home = column_text(s, 13);
    r.heartbeat_ms = sqlite3_column_int64(s, 14);
    out.push_back(std::move(r));
  }
  if (rc != SQLITE_DONE) fail("cannot read captures");
  return out;
}

void SqliteStore::insert(const CaptureRecord& r) {
  std::lock_guard<std::mutex> lock(mutex_);
  Stmt st = prepare(
      fmt::format("INSERT INTO captures ({}) VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)", kCaptureColumns));
  bind_record(st.get(), r, true);
  if (sqlite3_step(st.get()) != SQLITE_DONE) fail("cannot insert capture " + r.id);
}

std::optional<CaptureRecord> SqliteStore::get(const std::string& id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Stmt st = prepare(fmt::format("SELECT {} FROM captures WHERE id = ?", kCaptureColumns));
  sqlite3_bind_text(st.get(), 1, id.c_str(), -1, SQLITE_TRANSIENT);
  auto r = rows(st);
  if (r.empty()) return std::nullopt;
  return r.front();
}

bool SqliteStore::update(const CaptureRecord& r) { return update_row(r, nullptr); }

bool SqliteStore::update_owned(const CaptureRecord& r, const std::string& owner) {
  return update_row(r, &owner);
}

bool SqliteStore::update_row(const CaptureRecord& r, const std::string* owner) {
  std::lock_guard<std::mutex> lock(mutex_);
  Stmt st = prepare(
      std::string("UPDATE captures SET id = ?1, token_hash = ?2, state = ?3, stage = ?4, message = ?5, "
                  "percent = ?6, attempts = ?7, upload_kind = ?8, created_unix = ?9, updated_unix = ?10, "
                  "queued_unix = ?11, executor_job_id = ?12, owner = ?13, owner_home = ?14 WHERE id = ?1") +
      (owner ? " AND owner = ?15" : ""));
  CaptureRecord copy = r;
  copy.updated_unix = unix_now();
  bind_record(st.get(), copy, false);
  if (owner) sqlite3_bind_text(st.get(), 15, owner->c_str(), -1, SQLITE_TRANSIENT);
  if (sqlite3_step(st.get()) != SQLITE_DONE) fail("cannot update capture " + r.id);
  return sqlite3_changes(db_.get()) > 0;
}

bool SqliteStore::remove(const std::string& id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Stmt st = prepare("DELETE FROM captures WHERE id = ?");
  sqlite3_bind_text(st.get(), 1, id.c_str(), -1, SQLITE_TRANSIENT);
  if (sqlite3_step(st.get()) != SQLITE_DONE) fail("cannot delete capture " + id);
  return sqlite3_changes(db_.get()) > 0;
}

std::vector<CaptureRecord> SqliteStore::with_state(JobState s) {
  std::lock_guard<std::mutex> lock(mutex_);
  Stmt st = prepare(fmt::format(
      "SELECT {} FROM captures WHERE state = ? ORDER BY queued_unix, created_unix, id", kCaptureColumns));
  sqlite3_bind_text(st.get(), 1, to_string(s), -1, SQLITE_STATIC);
  return rows(st);
}

std::vector<std::string> SqliteStore::created_before(int64_t unix_seconds) {
  std::lock_guard<std::mutex> lock(mutex_);
  Stmt st = prepare("SELECT id FROM captures WHERE created_unix < ? ORDER BY created_unix");
  sqlite3_bind_int64(st.get(), 1, unix_seconds);
  std::vector<std::string> ids;
  while (sqlite3_step(st.get()) == SQLITE_ROW) ids.push_back(column_text(st.get(), 0));
  return ids;
}

std::map<JobState, int64_t> SqliteStore::count_by_state() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::map<JobState, int64_t> counts;
  for (JobState s :
       {JobState::Created, JobState::Queued, JobState::Running, JobState::Failed, JobState::Finished})
    counts[s] = 0;
  Stmt st = prepare("SELECT state, COUNT(*) FROM captures GROUP BY state");
  while (sqlite3_step(st.get()) == SQLITE_ROW)
    counts[job_state_from_string(column_text(st.get(), 0))] = sqlite3_column_int64(st.get(), 1);
  return counts;
}

std::vector<CaptureRecord> SqliteStore::select_ids(const std::vector<std::string>& ids) {
  std::vector<CaptureRecord> out;
  for (const std::string& id : ids) {
    Stmt st = prepare(fmt::format("SELECT {} FROM captures WHERE id = ?", kCaptureColumns));
    sqlite3_bind_text(st.get(), 1, id.c_str(), -1, SQLITE_TRANSIENT);
    for (auto& r : rows(st)) out.push_back(std::move(r));
  }
  return out;
}

std::optional<CaptureRecord> SqliteStore::claim_next(const JobOwner& by) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto claimed = transaction([&] {
    Stmt st = prepare(
        "SELECT id FROM captures WHERE state = 'queued' ORDER BY queued_unix, created_unix, id LIMIT 1");
    std::vector<std::string> ids;
    if (sqlite3_step(st.get()) == SQLITE_ROW) ids.push_back(column_text(st.get(), 0));
    if (ids.empty()) return ids;
    Stmt up = prepare(fmt::format(
        "UPDATE captures SET state = 'running', attempts = attempts + 1, updated_unix = ?, owner = ?, "
        "owner_home = ?, heartbeat_ms = {} WHERE id = ?",
        kSqliteNowMs));
    sqlite3_bind_int64(up.get(), 1, unix_now());
    sqlite3_bind_text(up.get(), 2, by.instance.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(up.get(), 3, by.home.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(up.get(), 4, ids[0].c_str(), -1, SQLITE_TRANSIENT);
    if (sqlite3_step(up.get()) != SQLITE_DONE) fail("cannot claim capture " + ids[0]);
    return ids;
  });
  auto r = select_ids(claimed);
  if (r.empty()) return std::nullopt;
  return r.front();
}

int SqliteStore::renew_leases(const std::string& owner) {
  std::lock_guard<std::mutex> lock(mutex_);
  Stmt st = prepare(fmt::format("UPDATE captures SET heartbeat_ms = {} WHERE state = 'running' AND owner = ?",
                                kSqliteNowMs));
  sqlite3_bind_text(st.get(), 1, owner.c_str(), -1, SQLITE_TRANSIENT);
  if (sqlite3_step(st.get()) != SQLITE_DONE) fail("cannot renew the leases of " + owner);
  return sqlite3_changes(db_.get());
}

std::vector<CaptureRecord> SqliteStore::adopt(const JobOwner& by, int64_t lease_ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto ids = transaction([&] {
    Stmt st = prepare(
        fmt::format("SELECT id FROM captures WHERE state = 'running' AND owner <> ?1 AND (owner_home = ?2 "
                    "OR heartbeat_ms < {} - ?3) ORDER BY queued_unix, id",
                    kSqliteNowMs));
    sqlite3_bind_text(st.get(), 1, by.instance.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(st.get(), 2, by.home.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_int64(st.get(), 3, lease_ms);
    std::vector<std::string> found;
    while (sqlite3_step(st.get()) == SQLITE_ROW) found.push_back(column_text(st.get(), 0));
    for (const std::string& id : found) {
      Stmt up = prepare(fmt::format(
          "UPDATE captures SET owner = ?, owner_home = ?, heartbeat_ms = {} WHERE id = ?", kSqliteNowMs));
      sqlite3_bind_text(up.get(), 1, by.instance.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(up.get(), 2, by.home.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(up.get(), 3, id.c_str(), -1, SQLITE_TRANSIENT);
      if (sqlite3_step(up.get()) != SQLITE_DONE) fail("cannot adopt capture " + id);
    }
    return found;
  });
  return select_ids(ids);
}

}  // namespace

std::unique_ptr<JobStore> open_sqlite_store(const std::string& path) {
  return std::make_unique<SqliteStore>(path);
}

}  // namespace lorgnette::service
