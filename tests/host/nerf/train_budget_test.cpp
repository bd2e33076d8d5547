// The default training budget (host/nerf/train_budget.h): steps follow the parameter count and the
// batch exactly as the rule states, are rounded to hundreds and clamped; the description names the
// budget that applied.
#include "host/nerf/train_budget.h"

#include <gtest/gtest.h>

namespace lorgnette::nerf {
namespace {

TEST(TrainBudget, StepsFollowParametersAndBatch) {
  // The demo head: 5,242,880 parameters (2^18 table x 16 levels x 2 features, plus the MLPs' few
  // thousand, ignored here) at 2^16 samples: 25 * 5242880 / 65536 = 2000 steps exactly.
  EXPECT_EQ(default_training_steps(5242880, 16).steps, 2000u);
  // Half the batch, twice the steps: the same number of samples.
  EXPECT_EQ(default_training_steps(5242880, 15).steps, 4000u);
  // 25 * 3,000,000 / 65536 = 1144.0 -> 1100 (whole hundreds).
  EXPECT_EQ(default_training_steps(3000000, 16).steps, 1100u);
}

TEST(TrainBudget, RoomCapturesTrainFewerSamplesPerParameter) {
  // A room capture's 2^18 subject (6.1 M parameters on in2n-face): 17 * 6100000 / 65536 = 1582.4
  // -> 1600 steps, where the general rule gives 25 * 6100000 / 65536 = 2327 -> 2300.
  EXPECT_EQ(default_training_steps(6100000, 16, kRoomCaptureSamplesPerParameter).steps, 1600u);
  EXPECT_EQ(default_training_steps(6100000, 16).steps, 2300u);
  EXPECT_NE(default_training_steps(6100000, 16, kRoomCaptureSamplesPerParameter).why.find("17 samples"),
            std::string::npos);
}

TEST(TrainBudget, RoomCapturesTrainAtLeastTheirMinimumOnAGpuBatch) {
  // On a GPU's 2^18 batch the samples rule gives a 5.5 M-parameter room capture 17 * 5.5e6 / 262144 =
  // 356.7 -> 400 steps; the room capture's minimum raises it to 1000 and says so.
  const StepBudget gpu =
      default_training_steps(5500000, 18, kRoomCaptureSamplesPerParameter, kRoomCaptureMinSteps);
  EXPECT_EQ(gpu.steps, kRoomCaptureMinSteps);
  EXPECT_NE(gpu.why.find("raised to the minimum 1000"), std::string::npos) << gpu.why;
  // The CPU's 2^16 batch is above it and unchanged (17 * 6.1e6 / 65536 -> 1600).
  EXPECT_EQ(default_training_steps(6100000, 16, kRoomCaptureSamplesPerParameter, kRoomCaptureMinSteps).steps,
            1600u);
}

TEST(TrainBudget, ClampedAndSaysSo) {
  StepBudget small = default_training_steps(1000, 16);
  EXPECT_EQ(small.steps, kMinSteps);
  EXPECT_NE(small.why.find("minimum"), std::string::npos) << small.why;
  StepBudget huge = default_training_steps(uint64_t(1) << 32, 12);
  EXPECT_EQ(huge.steps, kMaxSteps);
  EXPECT_NE(huge.why.find("capped"), std::string::npos) << huge.why;
}

TEST(TrainBudget, DescriptionNamesTheBudget) {
  StepBudget b = default_training_steps(5242880, 16);
  EXPECT_NE(describe_budget(b.steps, 0.0, true, b.why).find("default budget: 2000 steps"), std::string::npos);
  EXPECT_EQ(describe_budget(500, 0.0, false, ""), "500 steps (given)");
  EXPECT_NE(describe_budget(0, 60.0, false, "").find("60 s of wall-clock"), std::string::npos);
}

}  // namespace
}  // namespace lorgnette::nerf
