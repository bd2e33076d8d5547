// `train` carries the dataset's scale.json into the model (host/nerf/train_job.h model_metric_scale):
// millimetres per model unit are those per dataset unit over the normalisation's scale; no file, no
// scale; a malformed file is refused with its name.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "host/dataset/metric_scale.h"
#include "host/nerf/train_job.h"

namespace lorgnette::nerf {
namespace {

namespace fs = std::filesystem;

TEST(MetricScaleCarry, ScaleJsonBecomesMillimetresPerModelUnit) {
  const fs::path dir = fs::temp_directory_path() / ("lgn_scale_carry_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  dataset::Dataset ds;
  ds.root = dir.string();
  SceneNormalisation n;
  n.scale = 0.5f;
  EXPECT_FALSE(model_metric_scale(ds, n).has_value());
  dataset::write_scale_json(ds.root, {"card", 200.0, 0.8, 9});
  auto s = model_metric_scale(ds, n);
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->source, "card");
  EXPECT_DOUBLE_EQ(s->mm_per_unit, 400.0);  // a model unit is two dataset units
  EXPECT_DOUBLE_EQ(s->uncertainty, 1.6);
  std::ofstream(dir / dataset::kScaleFile) << "{\"source\": \"card\", \"mm_per_unit\": -1}";
  try {
    model_metric_scale(ds, n);
    ADD_FAILURE() << "a negative scale was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("scale.json"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace lorgnette::nerf
