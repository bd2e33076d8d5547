// The training request (host/nerf/train_settings.h): every number checked against its range
// (host/util/bounds.h) with the flag's and Python's names, before any dataset is read; the model
// refusing a step that would march for hours; and the job of the demo's settings being the job it
// built by hand before (so its numbers do not change).
#include "host/nerf/train_settings.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "host/nerf/model.h"
#include "host/util/bounds.h"
#include "tests/common/range_error.h"

namespace lorgnette::nerf {
namespace {

using lorgnette::testing::range_error;

TEST(TrainSettings, OutOfRangeNumbersAreRefusedNamingFlagAndArgument) {
  TrainSettings s;
  s.steps = 0;
  EXPECT_HAS(range_error([&] { validate(s); }), "--steps (Python: steps) must be within 1..1e+07");
  s = {};
  s.seconds = std::nan("");
  EXPECT_HAS(range_error([&] { validate(s); }), "--seconds (Python: seconds) must be within 0.1..604800");
  s = {};
  s.downscale = 1000;
  EXPECT_HAS(range_error([&] { validate(s); }), "--downscale (Python: downscale) must be within 1..16");
  s = {};
  s.step = 1e-9f;
  EXPECT_HAS(range_error([&] { validate(s); }), "--step must be within 1e-06..10000");
  s = {};
  s.batch_log2 = 30;
  EXPECT_HAS(range_error([&] { train_job(s); }), "--batch-log2");
  s = {};
  s.hair_mm = -5.0;
  EXPECT_HAS(range_error([&] { train_load_options(s); }), "--hair (Python: hair_mm)");
  s = {};
  s.room.opacity_prior = std::numeric_limits<float>::quiet_NaN();
  EXPECT_HAS(range_error([&] { validate(s); }), "--opacity-prior");
  s = {};
  s.room.opacity_prior_start = 2000000;
  EXPECT_HAS(range_error([&] { validate(s); }), "--prior-start");
  s = {};
  s.steps = 10, s.seconds = 5.0;
  EXPECT_THROW(validate(s), std::invalid_argument);
  s = {};
  s.background = "sometimes";
  EXPECT_THROW(validate(s), std::invalid_argument);
  EXPECT_NO_THROW(validate(TrainSettings{}));
}

TEST(TrainSettings, AabbTextIsParsedWithinTheSceneRange) {
  EXPECT_HAS(range_error([] { parse_aabb("-1e30,-1,-1,1e30,1,1"); }),
             "--aabb must be within -100000..100000");
  EXPECT_THROW(parse_aabb("0,0,0,1,nan,1"), std::invalid_argument);  // "needs six numbers"
  EXPECT_HAS(range_error([] { parse_aabb("1,1,1,0,2,2"); }), "max must exceed min");
  EXPECT_THROW(parse_aabb("1,2,3"), std::invalid_argument);
  std::optional<Aabb> box = parse_aabb("-1,-2,-3,1,2,3.5");
  ASSERT_TRUE(box);
  EXPECT_EQ(box->min, (std::array<float, 3>{-1, -2, -3}));
  EXPECT_EQ(box->max, (std::array<float, 3>{1, 2, 3.5f}));
  EXPECT_FALSE(parse_aabb(""));
}

// The demo's stage before train_settings existed: batch 2^16, a step count, seed, snapshot path.
TEST(TrainSettings, TheDemosSettingsGiveTheJobItBuiltByHand) {
  TrainSettings s;
  s.batch_log2 = 16, s.steps = 2000, s.seed = 7, s.output = "out/head.lnerf", s.progress = false;
  TrainJob job = train_job(s), hand;
  hand.batch_log2 = 16, hand.train.steps = 2000, hand.train.seed = 7;
  hand.train.snapshot_path = "out/head.lnerf", hand.train.progress = false;
  EXPECT_EQ(job.batch_log2, hand.batch_log2);
  EXPECT_EQ(job.train.steps, hand.train.steps);
  EXPECT_EQ(job.train.seconds, hand.train.seconds);
  EXPECT_EQ(job.train.seed, hand.train.seed);
  EXPECT_EQ(job.train.snapshot_path, hand.train.snapshot_path);
  EXPECT_EQ(job.train.progress, hand.train.progress);
  EXPECT_EQ(job.train.adam.lr, hand.train.adam.lr);
  EXPECT_EQ(job.train.loss_kind, hand.train.loss_kind);
  EXPECT_EQ(job.train.snapshot_every_seconds, hand.train.snapshot_every_seconds);
  EXPECT_EQ(job.train.background.opacity_prior, hand.train.background.opacity_prior);
  EXPECT_EQ(job.train.background.room_clear, hand.train.background.room_clear);
  EXPECT_EQ(job.background, hand.background);
  EXPECT_EQ(job.deterministic, hand.deterministic);
  EXPECT_EQ(job.aabb_scale, hand.aabb_scale);
  EXPECT_EQ(job.sizing.use_masks, hand.sizing.use_masks);
  EXPECT_FALSE(job.sizing.aabb || job.sizing.step || job.sizing.finest_resolution || job.sizing.levels ||
               job.sizing.log2_table_size || job.sizing.occupancy_resolution);
}

TEST(NerfModel, RefusesAStepThatWouldMarchForHours) {
  cl::Runtime rt({"", "", false});
  field::FieldConfig config;
  config.log2_table_size = 10;
  config.finest_resolution = 32;
  Aabb box{{-1, -1, -1}, {1, 1, 1}};
  EXPECT_HAS(range_error([&] { NerfModel(rt, config, box, 16, 1e-9f, 256, 1, true); }),
             "steps across the box's diagonal");
  EXPECT_HAS(range_error([&] { NerfModel(rt, config, box, 16, 1.0f, 256, 1, true); }), "outside 8..16384");
  NerfModel ok(rt, config, box, 16, 0.01f, 256, 1, true);
  EXPECT_EQ(ok.max_samples_per_ray(), 348u);  // ceil(3.464 / 0.01) + 1
}

}  // namespace
}  // namespace lorgnette::nerf
