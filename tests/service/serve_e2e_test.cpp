// (LABELS slow, ~1-2 min on 2 cores) The whole service path on a real server: a synthetic head
// turn in a room (`synth --room`, 16 views at 256x192, encoded as an MP4 by ffmpeg) is uploaded,
// started, captured by COLMAP, trained at a tiny budget, and the job ends finished with its
// artifacts on disk and in the status. No catalogue: the fit stage is covered by job_run_test.
#include <gtest/gtest.h>

#include <optional>

#include "http_client.h"
#include "service_test_util.h"

using namespace lorgnette::service;
using namespace lorgnette::service::test;

TEST(ServeEndToEnd, ARoomVideoGoesFromUploadToAFinishedJob) {
  if (!fs::exists("/usr/bin/ffmpeg") || !fs::exists("/usr/bin/colmap"))
    GTEST_SKIP() << "needs ffmpeg and colmap (tools/setup-debian.sh)";
  fs::path dir = test_dir("service_e2e");
  ASSERT_EQ(run_cli({"-q", "synth", "--procedural", "--room", "1", "--views", "16", "--size", "256x192",
                     "--samples", "1", "-o", (dir / "room").string()},
                    dir / "synth.log"),
            0)
      << read_file(dir / "synth.log");
  ChildEnd enc = ChildProcess({"/usr/bin/ffmpeg", "-loglevel", "error", "-framerate", "8", "-i",
                               (dir / "room/images/%04d.png").string(), "-c:v", "libx264", "-pix_fmt",
                               "yuv420p", (dir / "room.mp4").string()},
                              (dir / "ffmpeg.log").string())
                     .wait();
  ASSERT_TRUE(enc.exited && enc.code == 0) << read_file(dir / "ffmpeg.log");

  fs::path data = dir / "data";
  fs::create_directories(data);
  ChildProcess server(
      {LGN_CLI_PATH, "serve", "--data", data.string(), "--port", "0", "--port-file", (data / "port").string(),
       "--capture-fps", "8", "--capture-max-side", "256", "--train-steps", "30", "--train-batch-log2", "12"},
      (dir / "serve.log").string());
  ASSERT_TRUE(wait_for([&] { return fs::exists(data / "port"); }, 60.0)) << read_file(dir / "serve.log");
  const uint16_t port = uint16_t(std::stoi(read_file(data / "port")));

  HttpReply created = http_request(port, "POST", "/api/v1/captures");
  ASSERT_EQ(created.status, 201) << created.body;
  const auto c = nlohmann::json::parse(created.body);
  const std::string id = c["id"], token = c["token"], base = "/api/v1/captures/" + id;
  HttpReply up = http_request(port, "PUT", base + "/video", token, read_file(dir / "room.mp4"));
  ASSERT_EQ(up.status, 201) << up.body;
  EXPECT_EQ(nlohmann::json::parse(up.body)["stored_as"], "video.mp4");
  ASSERT_EQ(http_request(port, "POST", base + "/start", token).status, 202);

  nlohmann::json st;
  const bool ended = wait_for(
      [&] {
        st = nlohmann::json::parse(http_request(port, "GET", base, token).body);
        return st["state"] == "finished" || st["state"] == "failed";
      },
      600.0);
  ASSERT_TRUE(ended) << st.dump(2) << read_file(dir / "serve.log");
  ASSERT_EQ(st["state"], "finished") << st.dump(2) << read_file(data / "captures" / id / "worker.log");
  EXPECT_DOUBLE_EQ(st["progress"].get<double>(), 100.0);
  EXPECT_EQ(st["attempts"], 1);
  EXPECT_FALSE(st["artifacts"].contains("model")) << st.dump(2);  // on disk, never served nor listed
  EXPECT_TRUE(fs::exists(data / "captures" / id / "model" / "head.lnerf"));
  EXPECT_TRUE(fs::exists(data / "captures" / id / "dataset" / "transforms.json"));
}
