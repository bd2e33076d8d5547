// `lorgnette serve` as a real process on a loopback ephemeral port, driven over HTTP: bad inputs get
// 4xx and the server keeps serving (over-limit, not-a-video, empty upload, missing or wrong token,
// another capture's token, ids that try to leave the data folder, malformed JSON), the admin
// endpoints need the admin token, DELETE removes the folder and the row, and after the server is
// SIGKILLed and restarted every capture is still there, a failed job stays failed and a running
// one is handed back to the queue. The full happy path (a synthetic room video through COLMAP,
// training and the fit stage) is the slow test at the end.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <optional>

#include "http_client.h"
#include "serve_process.h"
#include "service/content_type.h"
#include "service_test_util.h"

using namespace lorgnette::service;
using namespace lorgnette::service::test;

namespace {

const std::string& kAdminToken = kTestAdminToken;

// A server on an ephemeral port over `data` (its port file, token and log in the same folder);
// restartable on the same folder.
class Server : public ServeProcess {
 public:
  explicit Server(const fs::path& data,
                  std::vector<std::string> extra = {"--max-upload-mb", "1", "--train-steps", "30"})
      : ServeProcess(data, data, with_small_batch(std::move(extra))) {}
  void kill9() { stop(SIGKILL); }

 private:
  static std::vector<std::string> with_small_batch(std::vector<std::string> extra) {
    extra.insert(extra.begin(), {"--train-batch-log2", "12"});
    return extra;
  }
};

struct Capture {
  std::string id, token;
};

Capture create(const Server& s) {
  HttpReply r = http_request(s.port(), "POST", "/api/v1/captures", "", "{\"label\": \"test\"}");
  EXPECT_EQ(r.status, 201) << r.body;
  auto j = nlohmann::json::parse(r.body);
  return {j["id"], j["token"]};
}

std::string path(const Capture& c, const std::string& rest = "") { return "/api/v1/captures/" + c.id + rest; }

nlohmann::json status(const Server& s, const Capture& c) {
  HttpReply r = http_request(s.port(), "GET", path(c), c.token);
  EXPECT_EQ(r.status, 200) << r.body;
  return nlohmann::json::parse(r.body);
}

bool is_error(const HttpReply& r, int status, const std::string& code) {
  if (r.status != status) return false;
  auto j = nlohmann::json::parse(r.body, nullptr, false);
  return !j.is_discarded() && j["error"]["code"] == code && !j["error"]["message"].get<std::string>().empty();
}

}  // namespace

TEST(Serve, CreatesCapturesWithUnguessableIdsAndTokens) {
  fs::path data = test_dir("service_serve");
  Server s(data);
  Capture a = create(s), b = create(s);
  EXPECT_EQ(a.id.size(), 32u);     // 128 bits
  EXPECT_EQ(a.token.size(), 64u);  // 256 bits
  EXPECT_NE(a.id, b.id);
  EXPECT_NE(a.token, b.token);
  nlohmann::json st = status(s, a);
  EXPECT_EQ(st["state"], "created");
  EXPECT_EQ(st["expires_unix"].get<int64_t>() - st["created_unix"].get<int64_t>(), 30 * 86400);
  // The token is stored hashed: it appears nowhere in the data folder.
  for (const auto& e : fs::recursive_directory_iterator(data)) {
    if (!e.is_regular_file()) continue;
    EXPECT_EQ(read_file(e.path()).find(a.token), std::string::npos) << e.path();
  }
}

TEST(Serve, BadRequestsGet4xxAndTheServerKeepsServing) {
  fs::path data = test_dir("service_serve");
  Server s(data);
  Capture c = create(s), other = create(s);
  EXPECT_TRUE(is_error(http_request(s.port(), "POST", "/api/v1/captures", "", "{not json"), 400, "bad_json"));
  EXPECT_TRUE(is_error(http_request(s.port(), "POST", "/api/v1/captures", "", "[1,2]"), 400, "bad_json"));
  EXPECT_TRUE(
      is_error(http_request(s.port(), "POST", "/api/v1/captures", "", "{\"x\": 1}"), 400, "bad_json"));
  EXPECT_TRUE(is_error(http_request(s.port(), "GET", path(c)), 401, "unauthorised"));
  EXPECT_TRUE(is_error(http_request(s.port(), "GET", path(c), "wrong"), 404, "not_found"));
  EXPECT_TRUE(is_error(http_request(s.port(), "GET", path(c), other.token), 404, "not_found"));
  EXPECT_TRUE(is_error(http_request(s.port(), "DELETE", path(c), other.token), 404, "not_found"));
  for (const std::string& target : std::vector<std::string>{
           "/api/v1/captures/../../etc/passwd", "/api/v1/captures/%2e%2e%2f%2e%2e",
           "/api/v1/captures/" + c.id + "/../" + other.id, "/api/v1/captures/" + c.id + "x",
           "/api/v1/captures/" + c.id + "/video/../../x"})
    EXPECT_EQ(http_request(s.port(), "GET", target, c.token).status / 100, 4) << target;
  EXPECT_TRUE(is_error(http_request(s.port(), "PUT", path(c, "/video"), c.token, ""), 400, "empty_upload"));
  EXPECT_TRUE(is_error(http_request(s.port(), "PUT", path(c, "/video"), c.token, "plain text, no video"), 415,
                       "unsupported_content"));
  EXPECT_TRUE(is_error(http_request(s.port(), "POST", path(c, "/photos"), c.token, broken_mp4()), 415,
                       "unsupported_content"));  // a video is not a photo
  const HttpReply big =
      http_request(s.port(), "PUT", path(c, "/video"), c.token, broken_mp4() + std::string(1 << 20, 'x'));
  EXPECT_TRUE(is_error(big, 413, "too_large")) << big.status << " " << big.body;
  EXPECT_TRUE(is_error(http_request(s.port(), "POST", path(c, "/start"), c.token), 409, "no_upload"));
  // Nothing half-written stays in the upload folder; the server still answers.
  EXPECT_TRUE(fs::is_empty(data / "captures" / c.id / "upload"));
  EXPECT_EQ(status(s, c)["state"], "created");
  EXPECT_EQ(http_request(s.port(), "GET", "/api/v1/health").status, 200);
  // The admin endpoints need the admin token, and count what was refused.
  EXPECT_TRUE(is_error(http_request(s.port(), "GET", "/metrics", c.token), 401, "unauthorised"));
  HttpReply m = http_request(s.port(), "GET", "/metrics", kAdminToken);
  ASSERT_EQ(m.status, 200);
  EXPECT_NE(m.body.find("lorgnette_jobs{state=\"created\"} 2\n"), std::string::npos) << m.body;
  EXPECT_NE(m.body.find("lorgnette_uploads_rejected_total{reason=\"unsupported_content\"} 2\n"),
            std::string::npos);
  EXPECT_NE(m.body.find("lorgnette_uploads_rejected_total{reason=\"too_large\"} 1\n"), std::string::npos);
  EXPECT_NE(m.body.find("# TYPE lorgnette_queue_length gauge\nlorgnette_queue_length 0\n"),
            std::string::npos);
}

TEST(Serve, StreamsAnUploadToDiskAndDeleteRemovesEverythingMadeFromIt) {
  fs::path data = test_dir("service_serve");
  Server s(data, {"--max-upload-mb", "3", "--train-steps", "30"});
  Capture c = create(s);
  // 2.5 MB, above Beast's default body limit of 1 MB: streamed whole to disk under the server's own limit.
  const std::string video = broken_mp4() + std::string(2'500'000, 'v');
  HttpReply up = http_request(s.port(), "PUT", path(c, "/video"), c.token, video);
  ASSERT_EQ(up.status, 201) << up.body;
  EXPECT_EQ(nlohmann::json::parse(up.body)["bytes"], video.size());
  EXPECT_EQ(read_file(data / "captures" / c.id / "upload" / "video.mp4"), video);
  EXPECT_EQ(http_request(s.port(), "DELETE", path(c), c.token).status, 204);
  EXPECT_FALSE(fs::exists(data / "captures" / c.id));
  EXPECT_TRUE(is_error(http_request(s.port(), "GET", path(c), c.token), 404, "not_found"));
}

TEST(Serve, AfterAServerSigkillEveryCaptureIsThereAndRunningJobsAreRequeued) {
  fs::path data = test_dir("service_serve");
  Server s(data);
  Capture failed = create(s), running = create(s);
  ASSERT_EQ(http_request(s.port(), "PUT", path(failed, "/video"), failed.token, broken_mp4()).status, 201);
  ASSERT_EQ(http_request(s.port(), "POST", path(failed, "/start"), failed.token).status, 202);
  ASSERT_TRUE(wait_for([&] { return status(s, failed)["state"] == "failed"; }, 60.0)) << s.log();
  const std::string message = status(s, failed)["message"];
  EXPECT_EQ(status(s, failed)["stage"], "capture");
  // A job that stays running: a capture folder whose worker waits for job.lock, held here.
  ASSERT_EQ(http_request(s.port(), "PUT", path(running, "/video"), running.token, broken_mp4()).status, 201);
  int lock_fd =
      ::open((data / "captures" / running.id / "job.lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  ASSERT_EQ(::flock(lock_fd, LOCK_EX), 0);
  ASSERT_EQ(http_request(s.port(), "POST", path(running, "/start"), running.token).status, 202);
  ASSERT_TRUE(wait_for([&] { return status(s, running)["state"] == "running"; }, 30.0));
  s.kill9();
  s.start();
  // The worker died with its server (no orphan to run beside the new one); the job is queued and
  // taken again: attempt 2, still waiting on the lock.
  ASSERT_TRUE(wait_for([&] { return status(s, running)["attempts"] == 2; }, 30.0)) << s.log();
  EXPECT_EQ(status(s, running)["state"], "running");
  EXPECT_NE(s.log().find("reconciled 1 running job"), std::string::npos) << s.log();
  EXPECT_EQ(status(s, failed)["state"], "failed");
  EXPECT_EQ(status(s, failed)["message"], message);
  ::close(lock_fd);  // the worker now runs the capture, which refuses the broken video
  ASSERT_TRUE(wait_for([&] { return status(s, running)["state"] == "failed"; }, 60.0)) << s.log();
  EXPECT_EQ(status(s, running)["attempts"], 2);
}

TEST(Serve, SigtermHandsARunningTrainingBackToTheQueueAndExitsCleanly) {
  fs::path data = test_dir("service_serve");
  Server s(data, {"--max-upload-mb", "1", "--train-steps", "3000"});  // a training that runs for minutes
  Capture c = create(s);
  // The capture stage already done (the tiny dataset), so the job goes straight to training.
  fs::copy(tiny_dataset(), data / "captures" / c.id / "dataset", fs::copy_options::recursive);
  ASSERT_EQ(http_request(s.port(), "PUT", path(c, "/video"), c.token, broken_mp4()).status, 201);
  ASSERT_EQ(http_request(s.port(), "POST", path(c, "/start"), c.token).status, 202);
  ASSERT_TRUE(wait_for(
      [&] {
        nlohmann::json st = status(s, c);
        return st["stage"] == "train" && st["progress"].get<double>() > 20.0;
      },
      120.0))
      << s.log();
  const ChildEnd end = s.stop(SIGTERM);
  EXPECT_TRUE(end.exited && end.code == 0) << s.log();
  EXPECT_NE(s.log().find("now queued"), std::string::npos) << s.log();
  EXPECT_FALSE(fs::exists(data / "captures" / c.id / "model"));  // nothing half-written
  s.start();
  nlohmann::json st = status(s, c);
  EXPECT_TRUE(st["state"] == "queued" || st["state"] == "running") << st.dump(2);
  EXPECT_EQ(http_request(s.port(), "DELETE", path(c), c.token).status, 204);
}
