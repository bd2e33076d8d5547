// `lorgnette job run` as a worker process over a capture folder: a job trains and finishes, a second
// run skips the stages already done (same bytes), a bad upload fails with the capture's own message
// and leaves no stage output, a worker killed during training leaves no model and the rerun
// resumes from the training checkpoint and finishes, a fit that finds no face fails the job with the fit's
// message at the fit stage, and SIGTERM during a fit hands the job back instead of failing it.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <optional>

#include "host/nerf/snapshot.h"
#include "service/job_settings.h"
#include "service/progress.h"
#include "service/stage.h"
#include "service_test_util.h"

using namespace lorgnette::service;
using namespace lorgnette::service::test;

namespace {

// A capture folder whose capture stage already ran (the tiny dataset in dataset/), so the test
// trains without COLMAP; `steps` of 2^12 samples.
fs::path captured_job(uint64_t steps, const std::string& catalogue = "", int fit_resolution = 64,
                      double snapshot_seconds = 60.0) {
  fs::path job = test_dir("service_job");
  fs::copy(tiny_dataset(), job / "dataset", fs::copy_options::recursive);
  JobSettings s;
  s.train_steps = steps;
  s.train_batch_log2 = 12;
  s.catalogue = catalogue;
  s.fit_views = 4;
  s.fit_resolution = fit_resolution;
  s.train_snapshot_seconds = snapshot_seconds;
  write_job_settings(job / "job.json", s);
  return job;
}

int job_run(const fs::path& job) { return run_cli({"job", "run", job.string()}, job / "worker.log"); }

}  // namespace

TEST(JobRun, TrainsAndFinishesThenSkipsTheStagesAlreadyDone) {
  fs::path job = captured_job(30);
  ASSERT_EQ(job_run(job), 0) << read_file(job / "worker.log");
  nlohmann::json p = read_json(job / "progress.json");
  EXPECT_EQ(p["state"], "finished");
  EXPECT_DOUBLE_EQ(p["percent"].get<double>(), 100.0);
  EXPECT_EQ(p["artifacts"]["model"], "model/head.lnerf");
  const std::string model = read_file(job / "model" / "head.lnerf");
  EXPECT_EQ(lorgnette::nerf::parse_snapshot(model, "head.lnerf").metadata.steps, 30u);
  EXPECT_FALSE(fs::exists(partial_path(job / "model")));

  const auto mtime = fs::last_write_time(job / "model" / "head.lnerf");
  ASSERT_EQ(job_run(job), 0) << read_file(job / "worker.log");
  EXPECT_EQ(fs::last_write_time(job / "model" / "head.lnerf"), mtime);  // not trained again
  EXPECT_EQ(read_file(job / "model" / "head.lnerf"), model);
  EXPECT_EQ(read_json(job / "progress.json")["state"], "finished");
}

TEST(JobRun, AnUploadThatIsNotAVideoFailsWithTheCapturesMessage) {
  fs::path job = test_dir("service_job");
  write_job_settings(job / "job.json", JobSettings{});
  write_file(job / "upload" / "video.mp4", "this is a text file, not a video\n");
  EXPECT_EQ(job_run(job), 1);
  nlohmann::json p = read_json(job / "progress.json");
  EXPECT_EQ(p["state"], "failed");
  EXPECT_EQ(p["stage"], "capture");
  EXPECT_NE(p["message"].get<std::string>().find("video"), std::string::npos) << p["message"];
  EXPECT_FALSE(fs::exists(job / "dataset"));
  EXPECT_FALSE(fs::exists(partial_path(job / "dataset")));
}

TEST(JobRun, NoUploadFailsSayingWhatToUpload) {
  fs::path job = test_dir("service_job");
  write_job_settings(job / "job.json", JobSettings{});
  EXPECT_EQ(job_run(job), 1);
  nlohmann::json p = read_json(job / "progress.json");
  EXPECT_EQ(p["state"], "failed");
  EXPECT_NE(p["message"].get<std::string>().find("upload a video"), std::string::npos) << p["message"];
}

// The step a worker's log says training resumed at ("resuming at step N of M"), or nothing.
std::optional<uint64_t> resumed_at(const std::string& log, uint64_t of) {
  const std::string tail = fmt::format(" of {} ", of);
  const size_t at = log.find("resuming at step ");
  if (at == std::string::npos) return std::nullopt;
  const size_t num = at + std::string("resuming at step ").size();
  if (log.compare(log.find(' ', num), tail.size(), tail) != 0) return std::nullopt;
  return std::stoull(log.substr(num));
}

TEST(JobRun, AWorkerKilledDuringTrainingLeavesNoModelAndTheRerunResumesAndFinishes) {
  // 600 steps with a checkpoint every 0.5 s: training outlasts several checkpoints even where it
  // runs fast (200 steps took 1.8 s on a quiet 2-core machine, under a 2 s checkpoint interval).
  fs::path job = captured_job(600, "", 64, 0.5);
  {
    ChildProcess worker({LGN_CLI_PATH, "job", "run", job.string()}, (job / "killed.log").string());
    // Killed once training has reported progress and written a checkpoint (outside its partial folder).
    ASSERT_TRUE(wait_for(
        [&] {
          auto p = read_progress(job / "progress.json");
          return p && p->stage == "train" && p->percent > 21.0 && fs::exists(job / "train.ckpt");
        },
        120.0))
        << read_file(job / "killed.log");
    worker.signal(SIGKILL);
    ChildEnd end = worker.wait();
    EXPECT_EQ(end.signal, SIGKILL);
  }
  EXPECT_FALSE(fs::exists(job / "model"));
  ASSERT_TRUE(fs::exists(job / "train.ckpt"));
  ASSERT_EQ(job_run(job), 0) << read_file(job / "worker.log");
  // The retry took up the training where the checkpoint left it, not at step 0, and trained to the
  // budget once: the model holds 600 steps and the checkpoint is gone with the finished stage.
  const std::string log = read_file(job / "worker.log");
  const std::optional<uint64_t> from = resumed_at(log, 600);
  ASSERT_TRUE(from.has_value()) << log;
  EXPECT_GT(*from, 0u);
  EXPECT_LT(*from, 600u);
  EXPECT_EQ(read_file(job / "killed.log").find("resuming at step"), std::string::npos);
  EXPECT_FALSE(fs::exists(partial_path(job / "model")));
  EXPECT_FALSE(fs::exists(job / "train.ckpt"));
  EXPECT_EQ(lorgnette::nerf::read_snapshot((job / "model" / "head.lnerf").string()).metadata.steps, 600u);
  EXPECT_EQ(read_json(job / "progress.json")["state"], "finished");
}

TEST(JobRun, AFitThatFindsNoFaceFailsTheJobWithTheFitsMessage) {
  fs::path catalogue = test_dir("service_catalogue");
  ASSERT_EQ(run_cli({"glasses", "make", "-o", (catalogue / "round.glb").string()}, catalogue / "make.log"), 0)
      << read_file(catalogue / "make.log");
  fs::remove(catalogue / "make.log");
  // 30 steps of 2^12 samples make a blur, in which the detector finds no face.
  fs::path job = captured_job(30, catalogue.string());
  EXPECT_EQ(job_run(job), 1) << read_file(job / "worker.log");
  nlohmann::json p = read_json(job / "progress.json");
  EXPECT_EQ(p["state"], "failed");
  EXPECT_EQ(p["stage"], "fit");
  EXPECT_NE(p["message"].get<std::string>().find("no face found"), std::string::npos) << p["message"];
  EXPECT_TRUE(fs::exists(job / "model" / "head.lnerf"));  // the stages before stay done
  EXPECT_FALSE(fs::exists(job / "fits" / "round.glb"));
  EXPECT_FALSE(fs::exists(partial_path(job / "fits" / "round.glb")));
}

// A server stopping its workers (SIGTERM) during a fit: the fit ends at its next view with its own
// error, and the job is handed back (75, state "running"), never failed. 512 px views keep the fit
// busy for several seconds, so the signal arrives while it renders.
TEST(JobRun, SigtermDuringAFitHandsTheJobBackInsteadOfFailingIt) {
  fs::path catalogue = test_dir("service_catalogue");
  ASSERT_EQ(run_cli({"glasses", "make", "-o", (catalogue / "round.glb").string()}, catalogue / "make.log"), 0)
      << read_file(catalogue / "make.log");
  fs::remove(catalogue / "make.log");
  fs::path job = captured_job(30, catalogue.string(), 512);
  ChildProcess worker({LGN_CLI_PATH, "job", "run", job.string()}, (job / "worker.log").string());
  ASSERT_TRUE(wait_for(
      [&] {
        auto p = read_progress(job / "progress.json");
        return p && p->stage == "fit";
      },
      120.0))
      << read_file(job / "worker.log");
  worker.signal(SIGTERM);
  ChildEnd end = worker.wait();
  EXPECT_TRUE(end.exited);
  EXPECT_EQ(end.code, 75) << read_file(job / "worker.log");
  nlohmann::json p = read_json(job / "progress.json");
  EXPECT_EQ(p["state"], "running") << p.dump();
  EXPECT_TRUE(fs::exists(job / "model" / "head.lnerf"));  // the stages before stay done
  EXPECT_FALSE(fs::exists(job / "fits" / "round.glb"));
  EXPECT_FALSE(fs::exists(partial_path(job / "fits" / "round.glb")));
}
