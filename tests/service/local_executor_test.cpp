// The local executor with real worker processes (`lorgnette job run`) and a real SQLite store: a
// queued job runs to finished; a worker SIGKILLed during training is retried, resumes from the
// training checkpoint and finishes (two attempts, the model trained once to its full budget); after
// a "restart" (a new executor on the same store) running jobs are handed back to the queue and
// finish, finished ones stay finished; a job whose stage fails ends failed with the product's
// message and is not retried.
#include "service/local_executor.h"

#include <gtest/gtest.h>
#include <signal.h>

#include "host/nerf/snapshot.h"
#include "service/job_settings.h"
#include "service/progress.h"
#include "service/sqlite_store.h"
#include "service_test_util.h"

using namespace lorgnette::service;
using namespace lorgnette::service::test;

namespace {

struct ExecutorEnv {
  fs::path data;
  std::unique_ptr<JobStore> store;
  LocalExecutorOptions options;
};

ExecutorEnv make_setup() {
  ExecutorEnv s;
  s.data = test_dir("service_executor");
  s.store = open_sqlite_store((s.data / "jobs.sqlite").string());
  s.options.data_dir = s.data.string();
  s.options.worker_exe = LGN_CLI_PATH;
  s.options.max_attempts = 2;
  return s;
}

// A queued capture whose capture stage is done (the tiny dataset), training `steps` of 2^12.
void add_job(ExecutorEnv& s, const std::string& id, uint64_t steps, JobState state = JobState::Queued,
             double snapshot_seconds = 60.0) {
  fs::path job = s.data / "captures" / id;
  fs::create_directories(job);
  fs::copy(tiny_dataset(), job / "dataset", fs::copy_options::recursive);
  JobSettings js;
  js.train_steps = steps;
  js.train_batch_log2 = 12;
  js.train_snapshot_seconds = snapshot_seconds;
  write_job_settings(job / "job.json", js);
  CaptureRecord r;
  r.id = id, r.token_hash = "x", r.state = state, r.created_unix = unix_now(), r.queued_unix = unix_now();
  s.store->insert(r);
}

bool run_until(LocalExecutor& ex, JobStore& store, const std::string& id, JobState want, double seconds) {
  return wait_for(
      [&] {
        ex.tick();
        auto r = store.get(id);
        return r && r->state == want;
      },
      seconds);
}

}  // namespace

TEST(LocalExecutor, RunsAQueuedJobToFinished) {
  ExecutorEnv s = make_setup();
  add_job(s, "job1", 30);
  LocalExecutor ex(*s.store, s.options);
  ASSERT_TRUE(run_until(ex, *s.store, "job1", JobState::Finished, 120.0))
      << read_file(s.data / "captures/job1/worker.log");
  auto r = *s.store->get("job1");
  EXPECT_DOUBLE_EQ(r.percent, 100.0);
  EXPECT_EQ(r.attempts, 1);
  EXPECT_EQ(r.stage, "train");
  EXPECT_EQ(ex.running(), 0);
}

TEST(LocalExecutor, AWorkerKilledDuringTrainingIsRetriedAndFinishes) {
  ExecutorEnv s = make_setup();
  // 600 steps with a checkpoint every 0.5 s: training outlasts several checkpoints even where it
  // runs fast (200 steps can take under the 2 s of a longer interval).
  add_job(s, "job2", 600, JobState::Queued, 0.5);
  LocalExecutor ex(*s.store, s.options);
  const fs::path progress = s.data / "captures/job2/progress.json";
  ASSERT_TRUE(wait_for(
      [&] {
        ex.tick();
        auto p = read_progress(progress);
        return p && p->stage == "train" && p->percent > 21.0 &&
               fs::exists(s.data / "captures/job2/train.ckpt");
      },
      120.0));
  const pid_t pid = ex.worker_pid("job2");
  ASSERT_GT(pid, 0);
  ::kill(pid, SIGKILL);
  ASSERT_TRUE(wait_for(
      [&] {
        ex.tick();
        return s.store->get("job2")->attempts == 2;
      },
      30.0));
  EXPECT_NE(s.store->get("job2")->message.find("retrying"), std::string::npos);
  ASSERT_TRUE(run_until(ex, *s.store, "job2", JobState::Finished, 180.0))
      << read_file(s.data / "captures/job2/worker.log");
  EXPECT_EQ(s.store->get("job2")->attempts, 2);
  auto snap = lorgnette::nerf::read_snapshot((s.data / "captures/job2/model/head.lnerf").string());
  EXPECT_EQ(snap.metadata.steps, 600u);  // one whole training, not two halves
  // The retry resumed from the training checkpoint the killed worker left (both attempts append to
  // worker.log), so no step was trained twice; the checkpoint went with the finished stage.
  const std::string log = read_file(s.data / "captures/job2/worker.log");
  EXPECT_NE(log.find("resuming at step "), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(s.data / "captures/job2/train.ckpt"));
}

TEST(LocalExecutor, AfterARestartRunningJobsAreRequeuedAndFinishedOnesStay) {
  ExecutorEnv s = make_setup();
  add_job(s, "was-running", 30, JobState::Running);  // as a killed server left it
  add_job(s, "done", 30, JobState::Finished);
  LocalExecutor ex(*s.store, s.options);
  EXPECT_EQ(ex.reconcile(), 1);
  EXPECT_EQ(s.store->get("was-running")->state, JobState::Queued);
  ASSERT_TRUE(run_until(ex, *s.store, "was-running", JobState::Finished, 120.0));
  EXPECT_EQ(s.store->get("done")->state, JobState::Finished);
  EXPECT_FALSE(fs::exists(s.data / "captures/done/progress.json"));  // never run again
}

TEST(LocalExecutor, AFailingStageFailsTheJobWithItsMessageWithoutRetry) {
  ExecutorEnv s = make_setup();
  add_job(s, "bad", 30);
  fs::remove_all(s.data / "captures/bad/dataset");  // nothing captured, nothing uploaded
  LocalExecutor ex(*s.store, s.options);
  ASSERT_TRUE(run_until(ex, *s.store, "bad", JobState::Failed, 60.0));
  auto r = *s.store->get("bad");
  EXPECT_EQ(r.attempts, 1);
  EXPECT_EQ(r.stage, "capture");
  EXPECT_NE(r.message.find("upload a video"), std::string::npos) << r.message;
}
