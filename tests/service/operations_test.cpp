// The service as an operator runs it, on real `lorgnette serve` processes: /metrics reports the
// seconds of each stage and failures by cause for real jobs, in a format a strict reader accepts;
// an upload onto a disk that fills answers 507, leaves nothing behind and the server keeps
// serving; and the same server runs on a PostgreSQL store (`--db postgresql://...`, a real server
// started by the test) through a failed job, a SIGKILL and a restart, never logging the password.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>

#include "../common/scoped_tmpfs.h"
#include "http_client.h"
#include "postgres_server.h"
#include "prometheus_text.h"
#include "serve_process.h"
#include "service_test_util.h"

using namespace lorgnette::service;
using namespace lorgnette::service::test;

namespace {

struct Capture {
  std::string id, token;
};

Capture create(uint16_t port) {
  HttpReply r = http_request(port, "POST", "/api/v1/captures", "", "{}");
  EXPECT_EQ(r.status, 201) << r.body;
  auto j = nlohmann::json::parse(r.body);
  return {j["id"], j["token"]};
}

std::string path(const Capture& c, const std::string& rest = "") { return "/api/v1/captures/" + c.id + rest; }

nlohmann::json status(uint16_t port, const Capture& c) {
  HttpReply r = http_request(port, "GET", path(c), c.token);
  EXPECT_EQ(r.status, 200) << r.body;
  return nlohmann::json::parse(r.body, nullptr, false);
}

PromText metrics(uint16_t port) {
  HttpReply m = http_request(port, "GET", "/metrics", kTestAdminToken);
  EXPECT_EQ(m.status, 200) << m.body;
  return parse_prometheus(m.body);
}

}  // namespace

TEST(Operations, MetricsReportStageSecondsAndFailuresByCauseOfRealJobs) {
  const fs::path dir = test_dir("service_operations");
  ServeProcess s(dir / "data", dir / "state", {"--train-steps", "30", "--train-batch-log2", "12"});
  Capture refused = create(s.port()), trained = create(s.port());
  ASSERT_EQ(http_request(s.port(), "PUT", path(refused, "/video"), refused.token, broken_mp4()).status, 201);
  ASSERT_EQ(http_request(s.port(), "POST", path(refused, "/start"), refused.token).status, 202);
  ASSERT_TRUE(wait_for([&] { return status(s.port(), refused)["state"] == "failed"; }, 60.0)) << s.log();
  // The second job's capture stage is already done (the tiny dataset): it trains, then finishes
  // (no catalogue, so no fit).
  fs::copy(tiny_dataset(), dir / "data" / "captures" / trained.id / "dataset", fs::copy_options::recursive);
  ASSERT_EQ(http_request(s.port(), "PUT", path(trained, "/video"), trained.token, broken_mp4()).status, 201);
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(http_request(s.port(), "POST", path(trained, "/start"), trained.token).status, 202);
  ASSERT_TRUE(wait_for([&] { return status(s.port(), trained)["state"] == "finished"; }, 120.0)) << s.log();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  const PromText t = metrics(s.port());
  EXPECT_TRUE(histogram_errors(t).empty());
  EXPECT_EQ(t.value("lorgnette_job_failures_total", {{"stage", "capture"}, {"cause", "refused"}}), 1);
  EXPECT_EQ(t.value("lorgnette_jobs", {{"state", "failed"}}), 1);
  EXPECT_EQ(t.value("lorgnette_jobs", {{"state", "finished"}}), 1);
  // The training is one observation; it cannot have taken longer than the test watched the job
  // (plus one 0.2 s tick and the test's 50 ms polling), nor nothing.
  EXPECT_EQ(t.value("lorgnette_stage_seconds_count", {{"stage", "train"}}), 1);
  const double train = t.value("lorgnette_stage_seconds_sum", {{"stage", "train"}});
  EXPECT_GT(train, 0.0);
  EXPECT_LE(train, wall + 0.5);
  // The refused capture is a failure, not a completed stage; the trained job's capture was already
  // done (skipped in a moment), so it is counted at most once, and short, when a tick saw it.
  const double captures = t.value("lorgnette_stage_seconds_count", {{"stage", "capture"}});
  if (!std::isnan(captures)) {
    EXPECT_EQ(captures, 1);
    EXPECT_LE(t.value("lorgnette_stage_seconds_sum", {{"stage", "capture"}}), 1.0);
  }
}

TEST(Operations, AnUploadOntoAFullDiskAnswers507LeavesNothingAndTheServerKeepsServing) {
  const fs::path dir = test_dir("service_operations");
  lgn_test::ScopedTmpfs disk(dir / "data", 2 << 20);  // 2 MB for the data folder
  LGN_SKIP_UNLESS_MOUNTED(disk);
  ServeProcess s(dir / "data", dir / "state",
                 {"--db", (dir / "jobs.sqlite").string(), "--max-upload-mb", "8"});
  Capture c = create(s.port());
  const HttpReply full = http_request(s.port(), "PUT", path(c, "/video"), c.token, broken_mp4(3 << 20));
  ASSERT_EQ(full.status, 507) << full.body;
  EXPECT_EQ(nlohmann::json::parse(full.body)["error"]["code"], "insufficient_storage");
  const fs::path upload = dir / "data" / "captures" / c.id / "upload";
  EXPECT_TRUE(fs::is_empty(upload));  // the partial file is gone, and with it the space
  EXPECT_NE(s.log().find("full disk"), std::string::npos) << s.log();
  EXPECT_EQ(http_request(s.port(), "GET", "/api/v1/health").status, 200);
  EXPECT_EQ(status(s.port(), c)["state"], "created");
  EXPECT_EQ(http_request(s.port(), "PUT", path(c, "/video"), c.token, broken_mp4()).status, 201);
  EXPECT_EQ(metrics(s.port()).value("lorgnette_uploads_rejected_total", {{"reason", "insufficient_storage"}}),
            1);
}

TEST(Operations, ServeRunsOnAPostgresStoreThroughAFailureAKillAndARestart) {
  ScopedPostgres pg;
  LGN_SKIP_UNLESS_POSTGRES(pg);
  const fs::path dir = test_dir("service_operations");
  // A password in the connection string (the test server trusts its socket and ignores it): the
  // server must never write it anywhere.
  const std::string db =
      "postgresql://lorgnette:pg-secret-42@/postgres?host=" + pg.uri().substr(pg.uri().find("host=") + 5);
  ServeProcess s(dir / "data", dir / "state", {"--db", db});
  Capture c = create(s.port()), waiting = create(s.port());
  ASSERT_EQ(http_request(s.port(), "PUT", path(c, "/video"), c.token, broken_mp4()).status, 201);
  ASSERT_EQ(http_request(s.port(), "POST", path(c, "/start"), c.token).status, 202);
  ASSERT_TRUE(wait_for([&] { return status(s.port(), c)["state"] == "failed"; }, 60.0)) << s.log();
  const std::string message = status(s.port(), c)["message"];
  EXPECT_FALSE(message.empty());
  s.stop(SIGKILL);
  s.start();
  EXPECT_EQ(status(s.port(), c)["state"], "failed");
  EXPECT_EQ(status(s.port(), c)["message"], message);
  EXPECT_EQ(status(s.port(), waiting)["state"], "created");
  EXPECT_FALSE(fs::exists(dir / "data" / "jobs.sqlite"));  // the store is PostgreSQL's
  EXPECT_NE(s.log().find("store postgresql database 'postgres'"), std::string::npos) << s.log();
  EXPECT_EQ(s.log().find("pg-secret-42"), std::string::npos) << s.log();
  EXPECT_EQ(http_request(s.port(), "DELETE", path(c), c.token).status, 204);
  EXPECT_EQ(metrics(s.port()).value("lorgnette_jobs", {{"state", "failed"}}), 0);
}
