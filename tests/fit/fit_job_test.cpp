// The fit job on a NeRF (fit/fit_job.h) never reports ok for a model whose training could not
// separate the subject from its room (ModelMetadata::subject_problem, #13). The model is the viewer
// tests' tiny trained head (tests/viewer/make_fixture.sh), whose own fit by `lorgnette fit` with the
// same settings is ok: that placement is the control, so the refusal below comes from the
// subject_problem and nothing else. One fit, about 15 s on 2 cores.
#include "fit/fit_job.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "host/cl/runtime.h"
#include "host/nerf/model.h"

namespace lorgnette::fit {
namespace {

namespace fs = std::filesystem;
const fs::path kFixture = fs::path(LORGNETTE_TEST_TMP) / "viewer-fixture";

TEST(FitJob, AModelWithASubjectProblemIsNeverOk) {
  const fs::path glasses = kFixture / "catalogue" / "a-round.glb";
  const fs::path control = kFixture / "catalogue" / "a-round.glb.placement.json";
  ASSERT_TRUE(fs::exists(control)) << "the viewer fixture is missing: run ctest -R viewer_fixture";
  ASSERT_TRUE(read_placement(control.string()).ok)
      << "the fixture's own fit is not ok, so this test could not tell the subject_problem's effect";
  cl::Runtime rt;
  nerf::NerfModel model = nerf::NerfModel::load(rt, (kFixture / "head.lnerf").string());
  ASSERT_TRUE(model.metadata.subject_problem.empty());
  const std::string problem = "the subject fills the frame edge to edge (test)";
  model.metadata.subject_problem = problem;
  FitSettings settings;  // as the fixture's `lorgnette fit --views 8`
  settings.views = 8;
  FitJobResult job = run_fit_job(model, glasses.string(), fit_options(settings));
  EXPECT_FALSE(job.fit.ok);
  EXPECT_FALSE(job.placement.ok);
  const auto& w = job.fit.warnings;
  EXPECT_TRUE(std::any_of(w.begin(), w.end(), [&](const std::string& s) {
    return s.find(problem) != std::string::npos;
  })) << "no warning names the model's subject problem";
}

}  // namespace
}  // namespace lorgnette::fit
