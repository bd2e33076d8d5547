// The SQLite job store on a real database file: the schema is migrated once and recorded, rows
// round-trip every field, the queue hands out the oldest job once (attempts counted), counts and
// retention queries see what was written, and a database from a newer Lorgnette is refused.
#include "service/sqlite_store.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include "service/schema.h"
#include "service_test_util.h"

using namespace lorgnette::service;
using namespace lorgnette::service::test;

namespace {

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

TEST(SqliteStore, MigratesOnceAndRoundTripsEveryField) {
  fs::path db = test_dir("service_store") / "jobs.sqlite";
  {
    auto store = open_sqlite_store(db.string());
    EXPECT_EQ(store->schema_version(), latest_schema_version());
    CaptureRecord r = record("abc", JobState::Running, 1000, 1001);
    r.stage = "train", r.message = "training the head's model", r.percent = 42.5, r.attempts = 2;
    r.upload_kind = "video", r.executor_job_id = "4711";
    store->insert(r);
    EXPECT_THROW(store->insert(r), std::runtime_error);  // ids are unique
  }
  auto store = open_sqlite_store(db.string());  // reopened: no migration runs twice
  EXPECT_EQ(store->schema_version(), latest_schema_version());
  auto got = store->get("abc");
  ASSERT_TRUE(got);
  EXPECT_EQ(got->token_hash, "hash-of-abc");
  EXPECT_EQ(got->state, JobState::Running);
  EXPECT_EQ(got->stage, "train");
  EXPECT_EQ(got->message, "training the head's model");
  EXPECT_DOUBLE_EQ(got->percent, 42.5);
  EXPECT_EQ(got->attempts, 2);
  EXPECT_EQ(got->upload_kind, "video");
  EXPECT_EQ(got->created_unix, 1000);
  EXPECT_EQ(got->queued_unix, 1001);
  EXPECT_EQ(got->executor_job_id, "4711");
  EXPECT_FALSE(store->get("abd"));
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

TEST(SqliteStore, ClaimsTheOldestQueuedJobOnceAndCountsAttempts) {
  auto store = open_sqlite_store((test_dir("service_store") / "jobs.sqlite").string());
  store->insert(record("late", JobState::Queued, 10, 300));
  store->insert(record("early", JobState::Queued, 20, 200));
  store->insert(record("new", JobState::Created, 30));
  auto first = store->claim_next();
  ASSERT_TRUE(first);
  EXPECT_EQ(first->id, "early");
  EXPECT_EQ(first->state, JobState::Running);
  EXPECT_EQ(first->attempts, 1);
  EXPECT_EQ(store->get("early")->attempts, 1);
  EXPECT_EQ(store->claim_next()->id, "late");
  EXPECT_FALSE(store->claim_next());  // "new" was never queued
  auto counts = store->count_by_state();
  EXPECT_EQ(counts[JobState::Running], 2);
  EXPECT_EQ(counts[JobState::Created], 1);
  EXPECT_EQ(counts[JobState::Queued], 0);
  EXPECT_EQ(store->with_state(JobState::Running).size(), 2u);
}

TEST(SqliteStore, UpdatesRemovesAndFindsCapturesPastRetention) {
  auto store = open_sqlite_store((test_dir("service_store") / "jobs.sqlite").string());
  store->insert(record("old", JobState::Finished, 100));
  store->insert(record("young", JobState::Finished, 500));
  EXPECT_EQ(store->created_before(200), std::vector<std::string>{"old"});
  CaptureRecord r = *store->get("young");
  r.state = JobState::Failed;
  r.message = "film from ear to ear";
  EXPECT_TRUE(store->update(r));
  EXPECT_EQ(store->get("young")->message, "film from ear to ear");
  EXPECT_GT(store->get("young")->updated_unix, 0);
  EXPECT_TRUE(store->remove("old"));
  EXPECT_FALSE(store->remove("old"));
  EXPECT_FALSE(store->get("old"));
  EXPECT_FALSE(store->update(record("gone", JobState::Queued, 1)));
}

TEST(SqliteStore, RefusesADatabaseFromANewerLorgnette) {
  fs::path db = test_dir("service_store") / "jobs.sqlite";
  open_sqlite_store(db.string());
  sqlite3* raw = nullptr;
  ASSERT_EQ(sqlite3_open(db.c_str(), &raw), SQLITE_OK);
  const std::string sql =
      "INSERT INTO schema_migrations VALUES (" + std::to_string(latest_schema_version() + 1) + ", 0)";
  ASSERT_EQ(sqlite3_exec(raw, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(raw);
  try {
    open_sqlite_store(db.string());
    FAIL() << "expected a refusal";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("newer than this Lorgnette"), std::string::npos) << e.what();
  }
}

TEST(SqliteStore, AnUnwritableLocationSaysWhichFile) {
  try {
    open_sqlite_store("/nonexistent-folder/jobs.sqlite");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-folder/jobs.sqlite"), std::string::npos) << e.what();
  }
}

TEST(SqliteStore, ADatabaseOfTheFirstSchemaGainsTheSchedulerJobIdAndKeepsItsRows) {
  fs::path db = test_dir("service_store") / "jobs.sqlite";
  {
    sqlite3* raw = nullptr;
    ASSERT_EQ(sqlite3_open(db.c_str(), &raw), SQLITE_OK);
    std::string sql =
        "CREATE TABLE schema_migrations (version INTEGER PRIMARY KEY, applied_unix BIGINT NOT NULL);"
        "INSERT INTO schema_migrations VALUES (1, 0);";
    for (const auto& s : migrations().at(0).statements) sql += s + ";";
    sql +=
        "INSERT INTO captures (id, token_hash, state, created_unix, updated_unix) VALUES ('old', 'h', "
        "'running', 5, 5);";
    ASSERT_EQ(sqlite3_exec(raw, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(raw);
    sqlite3_close(raw);
  }
  auto store = open_sqlite_store(db.string());
  EXPECT_EQ(store->schema_version(), latest_schema_version());
  auto got = store->get("old");
  ASSERT_TRUE(got);
  EXPECT_EQ(got->state, JobState::Running);
  EXPECT_EQ(got->executor_job_id, "");  // never submitted to a scheduler
  got->executor_job_id = "12";
  ASSERT_TRUE(store->update(*got));
  EXPECT_EQ(store->get("old")->executor_job_id, "12");
}
