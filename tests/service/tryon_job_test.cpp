// The fit stage's try-on views on the viewer tests' tiny trained head (fixture viewer_model,
// tests/viewer/make_fixture.sh) with one catalogue frame: `job run` fits the frame and renders the
// orbit of views into fits/<frame>/ (the status lists them), the head is drawn where the view's
// middle is and fills most of its height, the frame's dark rims are there; a rerun reuses the cached
// fit (same time), and a fit folder made from another model is made again. A frame that cannot be
// fitted (a file that does not load) is listed as unavailable with its reason and the job finishes
// with the others, and a frame added to the catalogue after the job finished is fitted when the try-on
// page asks for the job (queued again at its fit stage, the cached fit reused, the last finished
// files served meanwhile).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "fit/placement_json.h"
#include "host/util/image_io.h"
#include "service/api.h"
#include "service/job_folder.h"
#include "service/job_settings.h"
#include "service/local_executor.h"
#include "service/progress.h"
#include "service/sqlite_store.h"
#include "service_test_util.h"

using namespace lorgnette::service;
using namespace lorgnette::service::test;

namespace {

const fs::path kFixture = fs::path(LORGNETTE_TEST_TMP) / "viewer-fixture";

JobSettings small_fit_settings(const fs::path& catalogue) {
  JobSettings s;
  s.catalogue = catalogue.string();
  s.fit_views = 8;
  s.tryon_views = 3;
  s.tryon_size = 96;
  return s;
}

// The fixture's dataset and model in `job`: its capture and train stages are done.
void copy_trained_head(const fs::path& job) {
  fs::copy(kFixture / "dataset", job / "dataset", fs::copy_options::recursive);
  fs::create_directories(job / "model");
  fs::copy_file(kFixture / "head.lnerf", job / "model" / "head.lnerf");
}

fs::path trained_job(const fs::path& catalogue) {
  fs::path job = test_dir("service_tryon");
  copy_trained_head(job);
  write_job_settings(job / "job.json", small_fit_settings(catalogue));
  return job;
}

// The request body of a GET (none).
class NoBody final : public BodySource {
 public:
  std::string read_all(uint64_t) override { return ""; }
  uint64_t read_to_file(const fs::path&, uint64_t) override { return 0; }
};

int job_run(const fs::path& job) { return run_cli({"job", "run", job.string()}, job / "worker.log"); }

struct Coverage {
  double head_rows = 0;  // share of the image height between the first and last row with head pixels
  int dark = 0;          // pixels darker than any skin: the frame's rims
};

// Head pixels differ from the white background by more than 0.1 in some channel (linear RGB).
Coverage coverage(const lorgnette::Image& im) {
  Coverage c;
  int top = im.height, bottom = -1;
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      const float* p = &im.pixels[(size_t(y) * im.width + x) * im.channels];
      if (std::min({p[0], p[1], p[2]}) < 0.9f) top = std::min(top, y), bottom = std::max(bottom, y);
      if (std::max({p[0], p[1], p[2]}) < 0.08f) ++c.dark;
    }
  c.head_rows = bottom >= top ? double(bottom - top + 1) / im.height : 0.0;
  return c;
}

}  // namespace

TEST(TryOnJob, FitsOnceRendersTheViewsAndReusesThem) {
  if (!fs::exists(kFixture / "head.lnerf"))
    GTEST_SKIP() << "the viewer fixture is missing (ctest -R viewer_fixture)";
  fs::path catalogue = test_dir("service_tryon_catalogue");
  fs::copy_file(kFixture / "catalogue" / "a-round.glb", catalogue / "round.glb");
  const fs::path job = trained_job(catalogue);
  ASSERT_EQ(job_run(job), 0) << read_file(job / "worker.log");
  const auto p = read_progress(job / "progress.json");
  ASSERT_TRUE(p);
  const nlohmann::json& views = p->artifacts["views"]["round.glb"];
  ASSERT_EQ(views.size(), 3u) << p->artifacts.dump(2);
  EXPECT_EQ(p->artifacts["preview"], views[0]);
  EXPECT_EQ(p->artifacts["fits"]["round.glb"], "fits/round.glb/placement.json");
  for (const auto& v : views) {
    const lorgnette::Image im = lorgnette::read_image((job / v.get<std::string>()).string());
    ASSERT_EQ(im.width, 96);
    ASSERT_EQ(im.height, 96);
    const Coverage c = coverage(im);
    std::printf("%s: head over %.2f of the height, %d dark pixels\n", v.get<std::string>().c_str(),
                c.head_rows, c.dark);
    // The fixture's model box cuts the head at the neck and crown, so the head spans the framing
    // sphere's middle: at least 60 % of the height (the model's box alone frames it at ~45 %).
    EXPECT_GE(c.head_rows, 0.6) << v;
    EXPECT_GE(c.dark, 10) << v << ": no rims of the frame";
  }
  const fs::path view0 = job / views[0].get<std::string>();
  const auto made = fs::last_write_time(view0);
  ASSERT_EQ(job_run(job), 0) << read_file(job / "worker.log");  // everything cached: nothing redone
  EXPECT_EQ(fs::last_write_time(view0), made);
}

TEST(TryOnJob, AFitMadeFromAnotherModelIsMadeAgain) {
  if (!fs::exists(kFixture / "head.lnerf"))
    GTEST_SKIP() << "the viewer fixture is missing (ctest -R viewer_fixture)";
  fs::path catalogue = test_dir("service_tryon_catalogue");
  fs::copy_file(kFixture / "catalogue" / "a-round.glb", catalogue / "round.glb");
  const fs::path job = trained_job(catalogue);
  // What an earlier model (the capture trained again since) left: a complete fit folder.
  const fs::path fit = job / "fits" / "round.glb";
  write_file(fit / "placement.json", "{\"version\": 1, \"transform\": \"stale\"}\n");
  write_file(fit / "views.json", "[\"view_00.jpg\"]\n");
  write_file(fit / "view_00.jpg", "stale picture");
  write_file(fit / "made_from.json", "{\"model_hash\": \"0123456789abcdef\"}\n");
  ASSERT_EQ(job_run(job), 0) << read_file(job / "worker.log");
  EXPECT_EQ(lorgnette::read_image((fit / "view_00.jpg").string()).width, 96);
  EXPECT_NE(read_file(fit / "placement.json").find("\"landmarks\""), std::string::npos);
  const std::string model_hash = lorgnette::fit::file_hash((job / "model" / "head.lnerf").string());
  EXPECT_EQ(read_json(fit / "made_from.json")["model_hash"], model_hash);
  EXPECT_EQ(read_progress(job / "progress.json")->artifacts["views"]["round.glb"].size(), 3u);
}

// In-process API and local executor over a real worker, one job (one test, as each fit takes most
// of a minute on a loaded 2-core CPU): the catalogue's damaged frame file is listed as unavailable
// with the loader's reason and the job finishes with the frame that fitted; a frame is added to
// the catalogue; the next GET queues the job at its fit stage, serves the first frame's files
// meanwhile, and the job finishes with both frames, the first one's fit not made again.
TEST(TryOnJob, AnUnfittableFrameIsUnavailableAndAFrameAddedLaterIsFittedWhenAskedFor) {
  if (!fs::exists(kFixture / "head.lnerf"))
    GTEST_SKIP() << "the viewer fixture is missing (ctest -R viewer_fixture)";
  const fs::path data = test_dir("service_tryon_refit"), catalogue = data / "catalogue";
  fs::create_directories(catalogue);
  fs::copy_file(kFixture / "catalogue" / "a-round.glb", catalogue / "round.glb");
  write_file(catalogue / "a-broken.glb", "glTF but not really: a damaged upload of the shop's");
  auto store = open_sqlite_store((data / "jobs.sqlite").string());
  LocalExecutorOptions eo;
  eo.data_dir = data.string();
  eo.worker_exe = LGN_CLI_PATH;
  LocalExecutor executor(*store, eo);
  ApiOptions ao;
  ao.data_dir = data.string();
  ao.job = small_fit_settings(catalogue);
  Api api(ao, *store, executor);
  NoBody none;
  const auto made = nlohmann::json::parse(api.handle({"POST", "/api/v1/captures", "", 0}, none).body);
  const std::string id = made["id"], bearer = "Bearer " + made["token"].get<std::string>();
  auto get = [&](const std::string& rest = "") {
    return api.handle({"GET", "/api/v1/captures/" + id + rest, bearer, std::nullopt}, none);
  };
  copy_trained_head(data / "captures" / id);
  CaptureRecord rec = *store->get(id);
  rec.state = JobState::Queued, rec.upload_kind = "video";  // uploaded and started
  store->update(rec);
  auto run_to = [&](JobState want) {
    return wait_for(
        [&] {
          executor.tick();
          return store->get(id)->state == want;
        },
        240.0);
  };
  ASSERT_TRUE(run_to(JobState::Finished)) << read_file(data / "captures" / id / "worker.log");
  const nlohmann::json first = nlohmann::json::parse(get().body);
  EXPECT_EQ(first["state"], "finished");  // nothing new (an unavailable frame is known): stays finished
  EXPECT_EQ(first["artifacts"]["views"].size(), 1u) << first.dump(2);
  EXPECT_EQ(first["artifacts"]["preview"], first["artifacts"]["views"]["round.glb"][0]);  // the first fitted
  const std::string why = first["artifacts"]["unavailable"].value("a-broken.glb", "");
  EXPECT_NE(why.find("not a valid or supported glTF file"), std::string::npos) << first.dump(2);
  EXPECT_EQ(first.dump().find(catalogue.string()), std::string::npos) << first.dump(2);  // a server path
  EXPECT_FALSE(first["artifacts"]["fits"].contains("a-broken.glb"));
  EXPECT_FALSE(fs::exists(data / "captures" / id / "fits" / "a-broken.glb"));
  EXPECT_EQ(
      read_progress(data / "captures" / id / "progress.json")->artifacts["unavailable_from"]["a-broken.glb"],
      frame_file_hash((catalogue / "a-broken.glb").string()));  // tried again once the file changes
  const fs::path view0 = data / "captures" / id / "fits" / "round.glb" / "view_00.jpg";
  const auto round_made = fs::last_write_time(view0);

  fs::copy_file(kFixture / "catalogue" / "a-round.glb", catalogue / "round-2.glb");
  const nlohmann::json st = nlohmann::json::parse(get().body);
  EXPECT_EQ(st["state"], "queued");
  EXPECT_EQ(st["stage"], "fit");
  EXPECT_EQ(st["artifacts"]["views"].size(), 1u) << st.dump(2);
  EXPECT_EQ(st["artifacts"]["pending"], nlohmann::json::array({"round-2.glb"}));
  EXPECT_EQ(get("/artifacts/fits/round.glb/view_00.jpg").status, 200);  // the last finished files

  ASSERT_TRUE(run_to(JobState::Finished)) << read_file(data / "captures" / id / "worker.log");
  const nlohmann::json done = nlohmann::json::parse(get().body);
  EXPECT_EQ(done["state"], "finished");
  EXPECT_EQ(done["artifacts"]["views"].size(), 2u) << done.dump(2);
  EXPECT_EQ(done["artifacts"]["views"]["round-2.glb"].size(), 3u);
  EXPECT_TRUE(done["artifacts"]["unavailable"].contains("a-broken.glb"));
  EXPECT_FALSE(done["artifacts"].contains("pending"));
  EXPECT_EQ(fs::last_write_time(view0), round_made);  // the cached fit, not made again
  EXPECT_EQ(store->get(id)->attempts, 2);
  EXPECT_EQ(get("/artifacts/fits/round-2.glb/view_00.jpg").status, 200);
}
