// The fit stage's try-on views on the viewer tests' tiny trained head (fixture viewer_model,
// tests/viewer/make_fixture.sh) with one catalogue frame: `job run` fits the frame and renders the
// orbit of views into fits/<frame>/ (the status lists them), the head is drawn where the view's
// middle is and fills most of its height, the frame's dark rims are there; a rerun reuses the cached
// fit (same time), and a fit folder made from another model is made again.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "fit/placement_json.h"
#include "host/util/image_io.h"
#include "service/job_settings.h"
#include "service/progress.h"
#include "service_test_util.h"

using namespace lorgnette::service;
using namespace lorgnette::service::test;

namespace {

const fs::path kFixture = fs::path(LORGNETTE_TEST_TMP) / "viewer-fixture";

// A job whose capture and train stages are done: the fixture's dataset and model.
fs::path trained_job(const fs::path& catalogue) {
  fs::path job = test_dir("service_tryon");
  fs::copy(kFixture / "dataset", job / "dataset", fs::copy_options::recursive);
  fs::create_directories(job / "model");
  fs::copy_file(kFixture / "head.lnerf", job / "model" / "head.lnerf");
  JobSettings s;
  s.catalogue = catalogue.string();
  s.fit_views = 8;
  s.tryon_views = 3;
  s.tryon_size = 96;
  write_job_settings(job / "job.json", s);
  return job;
}

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
