// (LABELS slow, ~90 s) The Slurm executor against a real one-node Slurm cluster started by each test
// (slurm_cluster.h), with real `lorgnette job run` workers on the tiny synthetic head:
//   - a job goes through sbatch to finished (one COMPLETED Slurm job named after the capture, its
//     output in worker.log, the model trained to its budget, its stages' seconds in /metrics);
//   - a submission the controller refuses (an unknown partition) is retried, then fails the job
//     with Slurm's reason (counted in /metrics as a start failure);
//   - DELETE on a capture whose Slurm job runs cancels it with scancel (the worker process ends);
//   - a server killed with SIGKILL and restarted re-attaches the running Slurm job by its stored id,
//     and the job finishes once: one Slurm job, one attempt, one whole training;
//   - a job Slurm requeues (as on a node failure) runs again under its id and finishes.
// The option and command checks need no cluster and always run. Skips with a message without root
// or Slurm.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <regex>

#include "host/nerf/snapshot.h"
#include "http_client.h"
#include "service/job_settings.h"
#include "service/progress.h"
#include "service/slurm_executor.h"
#include "service/sqlite_store.h"
#include "service_test_util.h"
#include "slurm_cluster.h"

using namespace lorgnette::service;
using namespace lorgnette::service::test;

namespace {

std::unique_ptr<SlurmCluster> g_cluster;
std::string g_unavailable;

class Slurm : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    g_unavailable = SlurmCluster::unavailable();
    if (g_unavailable.empty()) g_cluster = std::make_unique<SlurmCluster>();
  }
  static void TearDownTestSuite() { g_cluster.reset(); }
  void SetUp() override {
    if (!g_cluster) GTEST_SKIP() << "no Slurm test cluster: " << g_unavailable;
  }
};

// Lines of the jobcomp file (one per finished Slurm job) for the job named lgn-<id>.
std::vector<std::string> finished_slurm_jobs(const std::string& id) {
  std::vector<std::string> out;
  std::istringstream in(read_file(g_cluster->jobcomp()));
  for (std::string line; std::getline(in, line);)
    if (line.find(" Name=lgn-" + id + " ") != std::string::npos) out.push_back(line);
  return out;
}

// The Slurm job ids squeue knows for the job named lgn-<id> (any state).
std::vector<std::string> slurm_ids(const std::string& id) {
  std::vector<std::string> ids;
  std::istringstream in(
      g_cluster->client({"squeue", "--noheader", "--states=all", "--name=lgn-" + id, "--format=%i"}));
  for (std::string line; std::getline(in, line);) ids.push_back(line);
  return ids;
}

std::string slurm_state(const std::string& slurm_id) {
  std::string s =
      g_cluster->client({"squeue", "--noheader", "--states=all", "--jobs=" + slurm_id, "--format=%T"});
  return s.substr(0, s.find('\n'));
}

// Processes whose command line names `folder` (the job's `lorgnette job run <folder>`).
int processes_naming(const fs::path& folder) {
  int n = 0;
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string cmd = read_file(e.path() / "cmdline");
    if (cmd.find(std::string("job") + '\0' + "run" + '\0' + folder.string()) != std::string::npos) ++n;
  }
  return n;
}

// A capture folder whose capture stage is done (the tiny dataset), training `steps` of 2^12.
void make_job_folder(const fs::path& job, uint64_t steps) {
  fs::create_directories(job);
  fs::copy(tiny_dataset(), job / "dataset", fs::copy_options::recursive);
  JobSettings js;
  js.train_steps = steps;
  js.train_batch_log2 = 12;
  write_job_settings(job / "job.json", js);
}

void insert_queued(JobStore& store, const std::string& id) {
  CaptureRecord rec;
  rec.id = id, rec.token_hash = "x", rec.state = JobState::Queued;
  rec.created_unix = rec.queued_unix = unix_now();
  store.insert(rec);
}

}  // namespace

TEST(SlurmOptions, RefuseWhatCouldReachSbatchAsSomethingElse) {
  SlurmExecutorOptions o;
  o.data_dir = "/srv/lorgnette";
  o.partition = "gpu-h200", o.gres = "gpu:h200:1", o.sbatch_args = {"--time=02:00:00", "--exclusive"};
  EXPECT_NO_THROW(validate_slurm_options(o));
  auto refused = [&](auto edit, const std::string& says) {
    SlurmExecutorOptions bad = o;
    edit(bad);
    try {
      validate_slurm_options(bad);
      ADD_FAILURE() << "accepted; expected: " << says;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  refused([](auto& b) { b.partition = "gpu; rm -rf /"; }, "--slurm-partition");
  refused([](auto& b) { b.gres = "gpu:1 --wrap=x"; }, "--slurm-gres");
  refused([](auto& b) { b.sbatch_args = {"-o/tmp/x"}; }, "not one sbatch option");
  refused([](auto& b) { b.sbatch_args = {"--time=1\n#SBATCH --x"}; }, "not one sbatch option");
  refused([](auto& b) { b.sbatch_args = {"--output=/tmp/x"}; }, "sets what the executor sets");
  refused([](auto& b) { b.sbatch_args = {"--job-name=x"}; }, "sets what the executor sets");
  refused([](auto& b) { b.data_dir = "/srv/%j"; }, "pattern");
}

TEST(SlurmOptions, CommandsRunWithoutAShellAndTimeOut) {
  CommandResult r = run_command({"/bin/echo", "a;b", "$(x)"}, 10.0);
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out, "a;b $(x)\n");  // each argument reached echo as it was, uninterpreted
  r = run_command({"/bin/sleep", "5"}, 0.3);
  EXPECT_EQ(r.status, -1);
  EXPECT_NE(r.err.find("did not answer"), std::string::npos) << r.err;
  r = run_command({"/nonexistent/sbatch"}, 5.0);
  EXPECT_EQ(r.status, 127);
  EXPECT_TRUE(find_program("no-such-program-lgn").empty());
  EXPECT_EQ(find_program("sh", "/bin"), "/bin/sh");
  // An executor without the Slurm clients refuses to start, naming the package.
  const fs::path empty = test_dir("service_slurm_options");
  auto store = open_sqlite_store((empty / "jobs.sqlite").string());
  SlurmExecutorOptions o;
  o.data_dir = empty.string(), o.bin_dir = empty.string();
  try {
    SlurmExecutor ex(*store, o);
    ADD_FAILURE() << "started without sbatch";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("slurm-client"), std::string::npos) << e.what();
  }
}

TEST_F(Slurm, AJobGoesThroughSbatchToFinished) {
  const fs::path data = test_dir("service_slurm");
  auto store = open_sqlite_store((data / "jobs.sqlite").string());
  make_job_folder(data / "captures/job1", 30);
  insert_queued(*store, "job1");
  SlurmExecutorOptions o;
  o.data_dir = data.string(), o.worker_exe = LGN_CLI_PATH, o.poll_seconds = 0.5;
  SlurmExecutor ex(*store, o);
  ASSERT_TRUE(wait_for(
      [&] {
        ex.tick();
        return store->get("job1")->state == JobState::Finished;
      },
      120.0))
      << store->get("job1")->message << read_file(data / "captures/job1/worker.log");
  const CaptureRecord r = *store->get("job1");
  EXPECT_EQ(r.attempts, 1);
  EXPECT_DOUBLE_EQ(r.percent, 100.0);
  ASSERT_EQ(finished_slurm_jobs("job1").size(), 1u);
  EXPECT_NE(finished_slurm_jobs("job1")[0].find("JobId=" + r.executor_job_id + " "), std::string::npos);
  EXPECT_NE(finished_slurm_jobs("job1")[0].find("JobState=COMPLETED"), std::string::npos);
  // The worker's own log went to the job folder, and the batch script names the folder quoted.
  EXPECT_FALSE(read_file(data / "captures/job1/worker.log").empty());
  EXPECT_NE(read_file(data / "captures/job1/slurm-job.sh")
                .find("job run '" + (data / "captures/job1").string() + "'"),
            std::string::npos);
  auto snap = lorgnette::nerf::read_snapshot((data / "captures/job1/model/head.lnerf").string());
  EXPECT_EQ(snap.metadata.steps, 30u);
  EXPECT_EQ(ex.running(), 0);
  // /metrics' stage seconds: each stage the worker completed, once, with the seconds its own clock
  // measured (progress.json's stage_seconds); the capture stage was done already (near zero).
  const auto progress = read_progress(data / "captures/job1/progress.json");
  ASSERT_TRUE(progress);
  const std::string text = ex.metrics()->prometheus_text();
  for (const char* stage : {"capture", "train"}) {
    ASSERT_TRUE(progress->stage_seconds.contains(stage)) << progress->stage_seconds.dump();
    const double seconds = progress->stage_seconds[stage];
    EXPECT_NE(text.find(fmt::format("lorgnette_stage_seconds_count{{stage=\"{}\"}} 1\n", stage)),
              std::string::npos)
        << text;
    EXPECT_NE(text.find(fmt::format("lorgnette_stage_seconds_sum{{stage=\"{}\"}} {}\n", stage, seconds)),
              std::string::npos)
        << text;
  }
  EXPECT_GT(progress->stage_seconds["train"].get<double>(), 0.0);
  EXPECT_LT(progress->stage_seconds["capture"].get<double>(), 1.0);  // skipped: the dataset was there
}

TEST_F(Slurm, ASubmissionSlurmRefusesIsRetriedThenFailsWithSlurmsReason) {
  const fs::path data = test_dir("service_slurm");
  auto store = open_sqlite_store((data / "jobs.sqlite").string());
  fs::create_directories(data / "captures/nopart");  // never runs: no dataset needed
  insert_queued(*store, "nopart");
  SlurmExecutorOptions o;
  o.data_dir = data.string(), o.worker_exe = LGN_CLI_PATH, o.poll_seconds = 0.2, o.max_attempts = 2;
  o.partition = "no-such-partition";  // well-formed, so only the controller can refuse it
  SlurmExecutor ex(*store, o);
  ASSERT_TRUE(wait_for(
      [&] {
        ex.tick();
        return store->get("nopart")->state == JobState::Failed;
      },
      30.0))
      << store->get("nopart")->message;
  const CaptureRecord r = *store->get("nopart");
  EXPECT_EQ(r.attempts, 2);
  EXPECT_NE(r.message.find("sbatch failed"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("partition"), std::string::npos) << r.message;  // Slurm's own reason
  EXPECT_TRUE(r.executor_job_id.empty());
  // Counted in /metrics as a job whose worker could not be started (the first retry is not).
  EXPECT_NE(ex.metrics()->prometheus_text().find(
                "lorgnette_job_failures_total{stage=\"start\",cause=\"start\"} 1\n"),
            std::string::npos)
      << ex.metrics()->prometheus_text();
}

namespace {

// `lorgnette serve --executor slurm` on an ephemeral port over `data`; restartable.
class SlurmServer {
 public:
  explicit SlurmServer(const fs::path& data) : data_(data) { start(); }
  void start() {
    fs::remove(data_ / "port");
    process_.emplace(std::vector<std::string>{LGN_CLI_PATH, "serve", "--data", data_.string(), "--port", "0",
                                              "--port-file", (data_ / "port").string(), "--executor", "slurm",
                                              "--slurm-poll-seconds", "0.5", "--slurm-arg=--time=10",
                                              "--train-batch-log2", "12", "--train-steps", "3000"},
                     (data_ / "serve.log").string());
    if (!wait_for([&] { return fs::exists(data_ / "port"); }, 60.0))
      throw std::runtime_error("serve did not start: " + read_file(data_ / "serve.log"));
    port_ = uint16_t(std::stoi(read_file(data_ / "port")));
  }
  void kill9() {
    process_->signal(SIGKILL);
    process_->wait();
    process_.reset();
  }
  uint16_t port() const { return port_; }

 private:
  fs::path data_;
  std::optional<ChildProcess> process_;
  uint16_t port_ = 0;
};

struct Started {
  std::string id, token, base;
};

// A capture whose upload is a (never decoded) MP4 and whose dataset is already there, started.
Started start_capture(const SlurmServer& s, const fs::path& data, uint64_t steps) {
  HttpReply created = http_request(s.port(), "POST", "/api/v1/captures");
  EXPECT_EQ(created.status, 201) << created.body;
  const auto c = nlohmann::json::parse(created.body);
  Started st{c["id"], c["token"], "/api/v1/captures/" + c["id"].get<std::string>()};
  const fs::path job = data / "captures" / st.id;
  fs::copy(tiny_dataset(), job / "dataset", fs::copy_options::recursive);
  JobSettings js = read_job_settings(job / "job.json");
  js.train_steps = steps;  // the shop-wide budget is 3000: this job's own, shorter one
  write_job_settings(job / "job.json", js);
  const std::string mp4 = std::string(
                              "\0\0\0\x18"
                              "ftypmp42\0\0\0\0mp42isom",
                              24) +
                          std::string(2000, 'x');
  EXPECT_EQ(http_request(s.port(), "PUT", st.base + "/video", st.token, mp4).status, 201);
  EXPECT_EQ(http_request(s.port(), "POST", st.base + "/start", st.token).status, 202);
  return st;
}

nlohmann::json status_of(const SlurmServer& s, const Started& c) {
  HttpReply r = http_request(s.port(), "GET", c.base, c.token);
  return r.status == 200 ? nlohmann::json::parse(r.body) : nlohmann::json{{"state", "?"}, {"progress", 0}};
}

bool training(const SlurmServer& s, const Started& c) {
  auto st = status_of(s, c);
  return st["state"] == "running" && st["progress"].get<double>() > 21.0;
}

}  // namespace

TEST_F(Slurm, DeletingACaptureCancelsItsSlurmJob) {
  const fs::path data = test_dir("service_slurm");
  SlurmServer server(data);
  const Started c = start_capture(server, data, 3000);
  ASSERT_TRUE(wait_for([&] { return training(server, c); }, 60.0)) << status_of(server, c).dump();
  const std::vector<std::string> ids = slurm_ids(c.id);
  ASSERT_EQ(ids.size(), 1u);
  EXPECT_EQ(slurm_state(ids[0]), "RUNNING");
  EXPECT_EQ(processes_naming(data / "captures" / c.id), 1);
  ASSERT_EQ(http_request(server.port(), "DELETE", c.base, c.token).status, 204);
  EXPECT_TRUE(wait_for([&] { return slurm_state(ids[0]) == "CANCELLED"; }, 20.0)) << slurm_state(ids[0]);
  EXPECT_TRUE(wait_for([&] { return processes_naming(data / "captures" / c.id) == 0; }, 20.0));
  EXPECT_FALSE(fs::exists(data / "captures" / c.id));  // the stopped worker recreated nothing
  EXPECT_TRUE(finished_slurm_jobs(c.id).size() == 1 &&
              finished_slurm_jobs(c.id)[0].find("JobState=CANCELLED") != std::string::npos)
      << read_file(g_cluster->jobcomp());
}

TEST_F(Slurm, AServerKilledAndRestartedReattachesItsRunningSlurmJob) {
  const fs::path data = test_dir("service_slurm");
  SlurmServer server(data);
  const Started c = start_capture(server, data, 120);
  ASSERT_TRUE(wait_for([&] { return training(server, c); }, 60.0)) << status_of(server, c).dump();
  const std::vector<std::string> ids = slurm_ids(c.id);
  ASSERT_EQ(ids.size(), 1u);
  server.kill9();
  EXPECT_EQ(slurm_state(ids[0]), "RUNNING");  // the farm's job does not die with the server
  server.start();
  nlohmann::json st;
  ASSERT_TRUE(wait_for(
      [&] {
        st = status_of(server, c);
        return st["state"] == "finished" || st["state"] == "failed";
      },
      120.0))
      << st.dump();
  ASSERT_EQ(st["state"], "finished") << st.dump() << read_file(data / "captures" / c.id / "worker.log");
  EXPECT_EQ(st["attempts"], 1);
  EXPECT_EQ(slurm_ids(c.id), ids);  // re-attached: no second submission
  const auto done = finished_slurm_jobs(c.id);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_NE(done[0].find("JobId=" + ids[0] + " "), std::string::npos);
  auto snap = lorgnette::nerf::read_snapshot((data / "captures" / c.id / "model/head.lnerf").string());
  EXPECT_EQ(snap.metadata.steps, 120u);  // one whole training
  EXPECT_NE(read_file(data / "serve.log").find("re-attached 1 Slurm job"), std::string::npos);
}

TEST_F(Slurm, AJobSlurmRequeuesRunsAgainUnderItsIdAndFinishes) {
  // `scontrol requeue` is what Slurm does to a job whose node fails; it works only on jobs submitted
  // requeueable. The worker is stopped, the job runs again under the same id, the executor keeps
  // following it, and the job finishes without an attempt of ours.
  const fs::path data = test_dir("service_slurm");
  auto store = open_sqlite_store((data / "jobs.sqlite").string());
  make_job_folder(data / "captures/rq", 120);
  insert_queued(*store, "rq");
  SlurmExecutorOptions o;
  o.data_dir = data.string(), o.worker_exe = LGN_CLI_PATH, o.poll_seconds = 0.5;
  SlurmExecutor ex(*store, o);
  ASSERT_TRUE(wait_for(
      [&] {
        ex.tick();
        auto p = read_progress(data / "captures/rq/progress.json");
        return p && p->stage == "train" && p->percent > 21.0;
      },
      60.0));
  const std::string id = ex.slurm_job_id("rq");
  ASSERT_FALSE(id.empty());
  const CommandResult requeue = run_command({find_program("scontrol"), "requeue", id}, 30.0);
  ASSERT_TRUE(requeue.ok()) << requeue.err;
  ASSERT_TRUE(wait_for(
      [&] {
        ex.tick();
        return slurm_state(id) == "PENDING";
      },
      30.0))
      << slurm_state(id);
  g_cluster->client({"scontrol", "update", "jobid=" + id, "StartTime=now"});  // not Slurm's 2 min delay
  ASSERT_TRUE(wait_for(
      [&] {
        ex.tick();
        return store->get("rq")->state == JobState::Finished;
      },
      120.0))
      << store->get("rq")->message << read_file(data / "captures/rq/worker.log");
  EXPECT_EQ(store->get("rq")->attempts, 1);
  EXPECT_EQ(store->get("rq")->executor_job_id, id);
  EXPECT_NE(read_file(data / "captures/rq/worker.log").find("DUE TO JOB REQUEUE"), std::string::npos);
  auto snap = lorgnette::nerf::read_snapshot((data / "captures/rq/model/head.lnerf").string());
  EXPECT_EQ(snap.metadata.steps, 120u);
}
