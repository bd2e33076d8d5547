// The job store's contract, the same tests on a real SQLite file and a real PostgreSQL server
// (started by the test, postgres_server.h): the schema is migrated once and recorded (also when two
// servers open a new database at once), rows round-trip every field, the queue hands out the oldest
// job once (attempts counted), two connections claiming at once take every job exactly once,
// counts and retention queries see what was written, a database from a newer Lorgnette is refused,
// and an unreachable database is named in the error (a PostgreSQL password never is). Owners and
// leases: a claimed job carries its owner and a lease from the database's clock, only its owner
// writes it, and it is adopted only once its lease has expired or by a later process of its
// owner's home, by one server when several try at once.
#include <gtest/gtest.h>
#include <libpq-fe.h>
#include <sqlite3.h>

#include <atomic>
#include <set>
#include <thread>

#include "postgres_server.h"
#include "service/postgres_store.h"
#include "service/schema.h"
#include "service/sqlite_store.h"
#include "service/store_selection.h"
#include "service_test_util.h"

using namespace lorgnette::service;
using namespace lorgnette::service::test;

namespace {

struct SqliteBackend {
  fs::path file = test_dir("service_store_sqlite") / "jobs.sqlite";
  bool available() const { return true; }
  std::string why() const { return ""; }
  std::string db() const { return file.string(); }
  void exec_raw(const std::string& sql) const {
    sqlite3* raw = nullptr;
    ASSERT_EQ(sqlite3_open(file.c_str(), &raw), SQLITE_OK);
    EXPECT_EQ(sqlite3_exec(raw, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(raw);
    sqlite3_close(raw);
  }
  // A location that cannot be opened, and the part of it the error must name.
  std::pair<std::string, std::string> unreachable() const {
    return {"/nonexistent-folder/jobs.sqlite", "/nonexistent-folder/jobs.sqlite"};
  }
};

struct PostgresBackend {
  ScopedPostgres server;
  bool available() const { return server.running(); }
  std::string why() const { return server.why(); }
  std::string db() const { return server.conninfo(); }
  void exec_raw(const std::string& sql) const {
    PGconn* c = PQconnectdb(db().c_str());
    ASSERT_EQ(PQstatus(c), CONNECTION_OK) << PQerrorMessage(c);
    PGresult* r = PQexec(c, sql.c_str());
    EXPECT_EQ(PQresultStatus(r), PGRES_COMMAND_OK) << PQerrorMessage(c);
    PQclear(r);
    PQfinish(c);
  }
  std::pair<std::string, std::string> unreachable() const {
    return {"postgresql://shop:not-to-be-shown@/jobs?host=/nonexistent-folder", "/nonexistent-folder"};
  }
};

template <class Backend>
class JobStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!backend.available()) GTEST_SKIP() << backend.why();
  }
  std::unique_ptr<JobStore> open() { return open_job_store(backend.db()); }
  Backend backend;
};

struct BackendNames {
  template <class T>
  static std::string GetName(int) {
    return std::is_same_v<T, SqliteBackend> ? "SQLite" : "PostgreSQL";
  }
};
using Backends = ::testing::Types<SqliteBackend, PostgresBackend>;
TYPED_TEST_SUITE(JobStoreTest, Backends, BackendNames);

const JobOwner kServerA{"a-instance@host", "a-home@host"}, kServerB{"b-instance@host", "b-home@host"};
const JobOwner kServerARestarted{"a-second-instance@host", "a-home@host"};

int64_t unix_ms_now() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

CaptureRecord record(const std::string& id, JobState state, int64_t created, int64_t queued = 0) {
  CaptureRecord r;
  r.id = id;
  r.token_hash = "hash-of-" + id;
  r.state = state;
  r.created_unix = created;
  r.queued_unix = queued;
  return r;
}

}  // namespace

TYPED_TEST(JobStoreTest, MigratesOnceAndRoundTripsEveryField) {
  {
    auto store = this->open();
    EXPECT_EQ(store->schema_version(), latest_schema_version());
    CaptureRecord r = record("abc", JobState::Running, 1000, 1001);
    // Quotes, a semicolon and non-ASCII text: values are parameters, never spliced into SQL.
    r.stage = "train", r.message = "it's the head's model; 'quoted' \xC3\xA9t\xC3\xA9", r.percent = 1.0 / 3.0;
    r.attempts = 2, r.upload_kind = "video", r.executor_job_id = "4711";
    store->insert(r);
    EXPECT_THROW(store->insert(r), std::runtime_error);  // ids are unique
  }
  auto store = this->open();  // reopened: no migration runs twice
  EXPECT_EQ(store->schema_version(), latest_schema_version());
  auto got = store->get("abc");
  ASSERT_TRUE(got);
  EXPECT_EQ(got->token_hash, "hash-of-abc");
  EXPECT_EQ(got->state, JobState::Running);
  EXPECT_EQ(got->stage, "train");
  EXPECT_EQ(got->message, "it's the head's model; 'quoted' \xC3\xA9t\xC3\xA9");
  EXPECT_EQ(got->percent, 1.0 / 3.0);  // exactly: the double round-trips
  EXPECT_EQ(got->attempts, 2);
  EXPECT_EQ(got->upload_kind, "video");
  EXPECT_EQ(got->created_unix, 1000);
  EXPECT_EQ(got->queued_unix, 1001);
  EXPECT_EQ(got->executor_job_id, "4711");
  EXPECT_FALSE(store->get("abd"));
}

TYPED_TEST(JobStoreTest, TwoServersOpeningANewDatabaseAtOnceMigrateItOnce) {
  std::vector<std::unique_ptr<JobStore>> stores(2);
  std::vector<std::string> errors(2);
  std::vector<std::thread> threads;
  for (int i = 0; i < 2; ++i)
    threads.emplace_back([&, i] {
      try {
        stores[i] = this->open();
      } catch (const std::exception& e) {
        errors[i] = e.what();
      }
    });
  for (auto& t : threads) t.join();
  for (int i = 0; i < 2; ++i) {
    ASSERT_TRUE(stores[i]) << errors[i];
    EXPECT_EQ(stores[i]->schema_version(), latest_schema_version());
  }
  stores[0]->insert(record("one", JobState::Created, 1));
  EXPECT_TRUE(stores[1]->get("one"));  // one database, one table
}

TYPED_TEST(JobStoreTest, ClaimsTheOldestQueuedJobOnceAndCountsAttempts) {
  auto store = this->open();
  store->insert(record("late", JobState::Queued, 10, 300));
  store->insert(record("early", JobState::Queued, 20, 200));
  store->insert(record("new", JobState::Created, 30));
  auto first = store->claim_next(kServerA);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->id, "early");
  EXPECT_EQ(first->state, JobState::Running);
  EXPECT_EQ(first->attempts, 1);
  EXPECT_EQ(store->get("early")->attempts, 1);
  EXPECT_EQ(store->get("early")->state, JobState::Running);
  EXPECT_EQ(store->claim_next(kServerA)->id, "late");
  EXPECT_FALSE(store->claim_next(kServerA));  // "new" was never queued
  auto counts = store->count_by_state();
  EXPECT_EQ(counts[JobState::Running], 2);
  EXPECT_EQ(counts[JobState::Created], 1);
  EXPECT_EQ(counts[JobState::Queued], 0);
  EXPECT_EQ(counts[JobState::Finished], 0);
  EXPECT_EQ(store->with_state(JobState::Running).size(), 2u);
}

TYPED_TEST(JobStoreTest, TwoConnectionsClaimingAtOnceTakeEveryJobExactlyOnce) {
  constexpr int kJobs = 200;
  auto a = this->open(), b = this->open();
  for (int i = 0; i < kJobs; ++i) a->insert(record("job" + std::to_string(i), JobState::Queued, i, 100 + i));
  std::vector<std::string> claimed[2];
  std::atomic<int> ready{0};
  auto claim_all = [&](JobStore& store, std::vector<std::string>& out) {
    ++ready;
    while (ready < 2) {
    }
    while (auto r = store.claim_next(kServerA)) out.push_back(r->id);
  };
  std::thread ta(claim_all, std::ref(*a), std::ref(claimed[0]));
  std::thread tb(claim_all, std::ref(*b), std::ref(claimed[1]));
  ta.join(), tb.join();
  std::multiset<std::string> all(claimed[0].begin(), claimed[0].end());
  all.insert(claimed[1].begin(), claimed[1].end());
  EXPECT_EQ(all.size(), size_t(kJobs));
  EXPECT_EQ(std::set<std::string>(all.begin(), all.end()).size(), size_t(kJobs));  // none twice
  for (const CaptureRecord& r : a->with_state(JobState::Running)) EXPECT_EQ(r.attempts, 1) << r.id;
  EXPECT_EQ(a->count_by_state()[JobState::Running], kJobs);
  this->RecordProperty("claimed_by_first", int(claimed[0].size()));
  this->RecordProperty("claimed_by_second", int(claimed[1].size()));
}

TYPED_TEST(JobStoreTest, UpdatesRemovesAndFindsCapturesPastRetention) {
  auto store = this->open();
  store->insert(record("old", JobState::Finished, 100));
  store->insert(record("young", JobState::Finished, 500));
  EXPECT_EQ(store->created_before(200), std::vector<std::string>{"old"});
  EXPECT_EQ(store->created_before(501), (std::vector<std::string>{"old", "young"}));
  CaptureRecord r = *store->get("young");
  r.state = JobState::Failed;
  r.message = "film from ear to ear";
  EXPECT_TRUE(store->update(r));
  EXPECT_EQ(store->get("young")->message, "film from ear to ear");
  EXPECT_EQ(store->get("young")->state, JobState::Failed);
  EXPECT_GT(store->get("young")->updated_unix, 0);
  EXPECT_TRUE(store->remove("old"));
  EXPECT_FALSE(store->remove("old"));
  EXPECT_FALSE(store->get("old"));
  EXPECT_FALSE(store->update(record("gone", JobState::Queued, 1)));
}

TYPED_TEST(JobStoreTest, RefusesADatabaseFromANewerLorgnette) {
  this->open();
  this->backend.exec_raw("INSERT INTO schema_migrations VALUES (" +
                         std::to_string(latest_schema_version() + 1) + ", 0)");
  try {
    this->open();
    FAIL() << "expected a refusal";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("newer than this Lorgnette"), std::string::npos) << e.what();
  }
}

TYPED_TEST(JobStoreTest, ADatabaseOfTheFirstSchemaGainsTheSchedulerJobIdAndKeepsItsRows) {
  std::string sql =
      "CREATE TABLE schema_migrations (version INTEGER PRIMARY KEY, applied_unix BIGINT NOT NULL);"
      "INSERT INTO schema_migrations VALUES (1, 0);";
  for (const auto& s : migrations().at(0).statements) sql += s + ";";
  sql +=
      "INSERT INTO captures (id, token_hash, state, created_unix, updated_unix) VALUES ('old', 'h', "
      "'running', 5, 5);";
  this->backend.exec_raw(sql);
  auto store = this->open();
  EXPECT_EQ(store->schema_version(), latest_schema_version());
  auto got = store->get("old");
  ASSERT_TRUE(got);
  EXPECT_EQ(got->state, JobState::Running);
  EXPECT_EQ(got->executor_job_id, "");  // never submitted to a scheduler
  got->executor_job_id = "12";
  ASSERT_TRUE(store->update(*got));
  EXPECT_EQ(store->get("old")->executor_job_id, "12");
  // A running row from before owners: no owner, a lease long expired, so the first server adopts it.
  EXPECT_EQ(got->owner, "");
  auto adopted = store->adopt(kServerB, 60'000);
  ASSERT_EQ(adopted.size(), 1u);
  EXPECT_EQ(adopted[0].owner, kServerB.instance);
}

TYPED_TEST(JobStoreTest, AClaimedJobHasItsOwnerAndALeaseOnlyItsOwnerRenewsAndWrites) {
  auto store = this->open();
  store->insert(record("j", JobState::Queued, 1, 1));
  const int64_t before = unix_ms_now();
  auto j = store->claim_next(kServerA);
  const int64_t after = unix_ms_now();
  ASSERT_TRUE(j);
  EXPECT_EQ(j->owner, kServerA.instance);
  EXPECT_EQ(j->owner_home, kServerA.home);
  // The database's clock, on this machine: the same as ours within 2 s (clock reading and rounding).
  EXPECT_GE(j->heartbeat_ms, before - 2000);
  EXPECT_LE(j->heartbeat_ms, after + 2000);
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  EXPECT_EQ(store->renew_leases(kServerA.instance), 1);
  EXPECT_EQ(store->renew_leases(kServerB.instance), 0);
  EXPECT_GE(store->get("j")->heartbeat_ms, j->heartbeat_ms + 20);
  CaptureRecord r = *j;
  r.message = "written by B";
  EXPECT_FALSE(store->update_owned(r, kServerB.instance));
  r.message = "written by A";
  EXPECT_TRUE(store->update_owned(r, kServerA.instance));
  EXPECT_EQ(store->get("j")->message, "written by A");
  EXPECT_GE(store->get("j")->heartbeat_ms, j->heartbeat_ms + 20);  // an update keeps the lease
}

TYPED_TEST(JobStoreTest, AJobIsAdoptedOnlyWhenItsLeaseExpiredOrByALaterProcessOfItsHome) {
  auto store = this->open();
  for (const char* id : {"a1", "a2"}) store->insert(record(id, JobState::Queued, 1, 1));
  store->insert(record("b1", JobState::Queued, 1, 2));
  ASSERT_TRUE(store->claim_next(kServerA));
  ASSERT_TRUE(store->claim_next(kServerA));
  ASSERT_EQ(store->claim_next(kServerB)->id, "b1");
  // A live server's fresh leases are nobody else's; nor its own to adopt.
  EXPECT_TRUE(store->adopt(kServerB, 60'000).empty());
  EXPECT_TRUE(store->adopt(kServerA, 60'000).empty());
  // Server A restarted (its home, another instance): its earlier rows at once, not B's.
  auto mine = store->adopt(kServerARestarted, 60'000);
  ASSERT_EQ(mine.size(), 2u);
  for (const auto& r : mine) EXPECT_EQ(r.owner, kServerARestarted.instance) << r.id;
  EXPECT_EQ(store->get("b1")->owner, kServerB.instance);
  EXPECT_EQ(store->renew_leases(kServerA.instance), 0);  // the old process owns nothing now
  // B stops renewing: after 300 ms a lease of 100 ms has expired, and A takes b1 over; A's own are
  // renewed and stay.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_EQ(store->renew_leases(kServerARestarted.instance), 2);
  auto taken = store->adopt(kServerARestarted, 100);
  ASSERT_EQ(taken.size(), 1u);
  EXPECT_EQ(taken[0].id, "b1");
  EXPECT_EQ(taken[0].owner_home, kServerARestarted.home);
  EXPECT_EQ(taken[0].attempts, 1);  // adopting is not another attempt
  // Finished, queued and created rows are never adopted.
  store->insert(record("done", JobState::Finished, 1, 1));
  store->insert(record("waiting", JobState::Queued, 1, 1));
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(store->adopt(kServerB, 1).size(), 3u);
}

TYPED_TEST(JobStoreTest, TwoServersAdoptingExpiredJobsAtOnceTakeEachOnce) {
  constexpr int kJobs = 100;
  auto a = this->open(), b = this->open();
  for (int i = 0; i < kJobs; ++i) a->insert(record("job" + std::to_string(i), JobState::Queued, i, i));
  const JobOwner dead{"dead@host", "dead-home@host"};
  while (a->claim_next(dead)) {
  }
  // Their leases expire after 1 s, far longer than one adoption takes: a server never adopts what
  // the other has just adopted.
  std::this_thread::sleep_for(std::chrono::milliseconds(1200));
  std::vector<CaptureRecord> adopted[2];
  std::atomic<int> ready{0};
  auto adopt = [&](JobStore& store, const JobOwner& by, std::vector<CaptureRecord>& out) {
    ++ready;
    while (ready < 2) {
    }
    out = store.adopt(by, 1000);
  };
  std::thread ta(adopt, std::ref(*a), std::cref(kServerA), std::ref(adopted[0]));
  std::thread tb(adopt, std::ref(*b), std::cref(kServerB), std::ref(adopted[1]));
  ta.join(), tb.join();
  std::multiset<std::string> all;
  for (int k = 0; k < 2; ++k)
    for (const auto& r : adopted[k]) all.insert(r.id);
  EXPECT_EQ(all.size(), size_t(kJobs));
  EXPECT_EQ(std::set<std::string>(all.begin(), all.end()).size(), size_t(kJobs));  // none twice
  for (int k = 0; k < 2; ++k)
    for (const auto& r : adopted[k]) EXPECT_EQ(a->get(r.id)->owner, (k == 0 ? kServerA : kServerB).instance);
}

TYPED_TEST(JobStoreTest, AnUnreachableDatabaseIsNamedButNeverItsPassword) {
  const auto [db, named] = this->backend.unreachable();
  try {
    open_job_store(db);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("not-to-be-shown"), std::string::npos) << e.what();
  }
  EXPECT_EQ(describe_job_store(db).find("not-to-be-shown"), std::string::npos) << describe_job_store(db);
}

TEST(SqliteStore, UsesWriteAheadLogging) {
  const fs::path db = test_dir("service_store_sqlite") / "jobs.sqlite";
  open_sqlite_store(db.string());
  // WAL mode, as the header promises (readers never wait for the writer).
  sqlite3* raw = nullptr;
  ASSERT_EQ(sqlite3_open(db.c_str(), &raw), SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  sqlite3_prepare_v2(raw, "PRAGMA journal_mode", -1, &st, nullptr);
  ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);
  EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(st, 0)), "wal");
  sqlite3_finalize(st);
  sqlite3_close(raw);
}

TEST(StoreSelection, ConnectionStringsOpenPostgresAndPathsSqlite) {
  EXPECT_TRUE(is_postgres_conninfo("postgresql://shop@db.internal/lorgnette"));
  EXPECT_TRUE(is_postgres_conninfo("postgres://shop@db.internal/lorgnette"));
  EXPECT_TRUE(is_postgres_conninfo("host=/run/postgresql dbname=lorgnette"));
  EXPECT_TRUE(is_postgres_conninfo(" dbname = lorgnette"));
  EXPECT_FALSE(is_postgres_conninfo("/srv/lorgnette/jobs.sqlite"));
  EXPECT_FALSE(is_postgres_conninfo("jobs.sqlite"));
  EXPECT_FALSE(is_postgres_conninfo("./a=b.sqlite"));
  const std::string d = describe_job_store("postgresql://shop:s3cret@db.internal:5433/lorgnette");
  EXPECT_EQ(d, "postgresql database 'lorgnette' on 'db.internal:5433' as 'shop'");
  EXPECT_EQ(describe_job_store("host=/tmp password=s3cret dbname=x").find("s3cret"), std::string::npos);
  // A string libpq cannot read is refused before connecting, without quoting any of it.
  try {
    open_job_store("postgresql://shop:s3cr%zzet@db.internal/lorgnette");
    FAIL() << "expected a refusal";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("unreadable PostgreSQL connection string"), std::string::npos)
        << e.what();
    EXPECT_EQ(std::string(e.what()).find("s3cr"), std::string::npos) << e.what();
  }
}
