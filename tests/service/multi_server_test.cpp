// Several `lorgnette serve` processes on one job store and one data folder (real processes, a real
// PostgreSQL server the test starts, and the default SQLite file): a server restarted while another
// runs a job leaves that job alone (not requeued, not run twice, its lease kept alive across
// several lease lengths), and a server killed with SIGKILL has its job taken over by the other once
// the lease has expired, and finished there. Leases are 2 s here (--lease-seconds), 60 s by default.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "http_client.h"
#include "postgres_server.h"
#include "serve_process.h"
#include "service_test_util.h"

using namespace lorgnette::service;
using namespace lorgnette::service::test;

namespace {

struct Capture {
  std::string id, token;
};

nlohmann::json status(uint16_t port, const Capture& c) {
  HttpReply r = http_request(port, "GET", "/api/v1/captures/" + c.id, c.token);
  EXPECT_EQ(r.status, 200) << r.body;
  return nlohmann::json::parse(r.body, nullptr, false);
}

// A job that stays running on the server it is started through: its worker waits for the
// folder's job.lock, which the test holds (returned; closing it lets the worker go on).
int start_held_job(uint16_t port, const fs::path& data, Capture& c) {
  HttpReply r = http_request(port, "POST", "/api/v1/captures", "", "{}");
  EXPECT_EQ(r.status, 201) << r.body;
  auto j = nlohmann::json::parse(r.body);
  c = {j["id"], j["token"]};
  EXPECT_EQ(http_request(port, "PUT", "/api/v1/captures/" + c.id + "/video", c.token, broken_mp4()).status,
            201);
  const int fd = ::open((data / "captures" / c.id / "job.lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  EXPECT_EQ(::flock(fd, LOCK_EX), 0);
  EXPECT_EQ(http_request(port, "POST", "/api/v1/captures/" + c.id + "/start", c.token).status, 202);
  return fd;
}

// Server B runs a job; server A is restarted twice (SIGKILL, then SIGTERM) meanwhile, and B's job
// stays B's: one attempt, running, for 3 lease lengths. Then B is killed: A takes the job over
// once its lease expires and runs it to its end (the capture refuses the broken video).
void two_servers(const std::vector<std::string>& db) {
  const fs::path dir = test_dir("service_multi_server");
  const fs::path data = dir / "data";
  std::vector<std::string> extra{"--lease-seconds", "2", "--train-steps", "30", "--train-batch-log2", "12"};
  extra.insert(extra.end(), db.begin(), db.end());
  ServeProcess b(data, dir / "b", extra);
  Capture c;
  const int lock_fd = start_held_job(b.port(), data, c);
  ASSERT_TRUE(wait_for([&] { return status(b.port(), c)["state"] == "running"; }, 30.0)) << b.log();
  ServeProcess a(data, dir / "a", extra);
  a.stop(SIGKILL);
  a.start();
  a.stop(SIGTERM);
  a.start();
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(6);
  while (std::chrono::steady_clock::now() < until) {
    const nlohmann::json st = status(a.port(), c);
    ASSERT_EQ(st["state"], "running") << st.dump() << a.log();
    ASSERT_EQ(st["attempts"], 1) << st.dump() << a.log();
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  EXPECT_EQ(a.log().find("reconciled"), std::string::npos) << a.log();
  EXPECT_EQ(a.log().find("stopped renewing"), std::string::npos) << a.log();
  // The two servers took different homes in the shared data folder.
  EXPECT_NE(a.log().find(".1'"), std::string::npos) << a.log();
  EXPECT_NE(b.log().find(".0'"), std::string::npos) << b.log();

  b.stop(SIGKILL);  // its worker dies with it
  const auto killed = std::chrono::steady_clock::now();
  ASSERT_TRUE(wait_for([&] { return status(a.port(), c)["attempts"] == 2; }, 20.0)) << a.log();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - killed).count();
  EXPECT_GT(seconds, 0.5);  // not before the lease (2 s, renewed every 0.33 s) ran out
  EXPECT_LT(seconds, 6.0);  // the lease plus a check interval, with slack for a loaded machine
  EXPECT_NE(a.log().find("stopped renewing their lease"), std::string::npos) << a.log();
  EXPECT_EQ(status(a.port(), c)["state"], "running");
  ::close(lock_fd);
  ASSERT_TRUE(wait_for([&] { return status(a.port(), c)["state"] == "failed"; }, 60.0)) << a.log();
  const nlohmann::json st = status(a.port(), c);
  EXPECT_EQ(st["attempts"], 2);
  EXPECT_EQ(st["stage"], "capture");
}

}  // namespace

TEST(MultiServer, TwoServersOnOnePostgresKeepEachOthersJobsAndTakeOverADeadOnes) {
  ScopedPostgres pg;
  LGN_SKIP_UNLESS_POSTGRES(pg);
  two_servers({"--db", pg.uri()});
}

TEST(MultiServer, TwoServersOnOneSqliteFileKeepEachOthersJobsAndTakeOverADeadOnes) { two_servers({}); }
