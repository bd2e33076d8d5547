// How long to train when the user names no budget: a number of steps derived from the model's size,
// never from the clock, so every device trains the same model to the same quality and a fast GPU
// simply finishes sooner. A hash grid with more parameters sees each one less often per step, so it
// needs more samples: the budget is kSamplesPerParameter samples per trainable parameter, in steps of
// the chosen batch, within [kMinSteps, kMaxSteps]. Calibrated on the demo's procedural head (a 2^18
// table, 20 MB, which reaches ~35 dB held-out in ~2000 steps of 2^16 samples; BENCHMARKS.md).
#pragma once
#include <cstdint>
#include <string>

#include "host/nerf/sizing.h"

namespace lorgnette::nerf {

struct StepBudget {
  uint64_t steps = 0;
  std::string why;  // one line for logs and reports: the rule and its inputs
};

inline constexpr double kSamplesPerParameter = 25.0;
inline constexpr uint64_t kMinSteps = 500, kMaxSteps = 20000;

// Captures trained with a room model (mask-less, subject box: background_field.h) cap the subject's
// hash table at 2^kRoomCaptureMaxLog2Table. Their box has no carved hull, so the sizing's surface
// estimate is the box's whole surface and hits the 2^19 ceiling; a real capture must reach a fitted
// try-on within 4 minutes on a 2-core CPU, and the default budget of a 2^19 model did not (in2n-face:
// 11.4 M parameters, 4300 steps, 463 s on the quiet machine). At 2^18 the rule above gives 2300
// steps (6.1 M parameters); docs/room-training.md ("Budgets") has the face PSNR against the 2^19 runs.
inline constexpr uint32_t kRoomCaptureMaxLog2Table = 18;
// And train kRoomCaptureSamplesPerParameter samples per parameter instead of kSamplesPerParameter:
// on in2n-face 25 takes about 270 s on the 2-core CPU for 24.89 dB of face, 17 about 197 s for
// 24.71 dB, and only 17 leaves the fit a margin within 4 minutes (docs/room-training.md, "Budgets").
inline constexpr double kRoomCaptureSamplesPerParameter = 17.0;
// And at least kRoomCaptureMinSteps steps: separating the subject from the room takes optimizer
// steps, not only samples. A GPU's 2^18 batch gives a room capture about 400 steps by the rule
// above, and 500 steps leaked 2.72 % of the subject's area where 1000 leak 1.89 % (NVIDIA H200;
// docs/room-training.md, "Budgets"). The 2-core CPU's budget (2^16: 1400-1600 steps) lies above it.
inline constexpr uint64_t kRoomCaptureMinSteps = 1000;

// The default number of training steps for a model of `parameters` floats trained with 2^batch_log2
// samples per step, at least min_steps.
StepBudget default_training_steps(uint64_t parameters, uint32_t batch_log2,
                                  double samples_per_parameter = kSamplesPerParameter,
                                  uint64_t min_steps = kMinSteps);

// A one-line description of the budget a run used: "2000 steps (default for a 5.2 M-parameter model)",
// "--steps 500", "--seconds 60 (time budget)".
std::string describe_budget(uint64_t steps, double seconds, bool defaulted, const std::string& default_why);

}  // namespace lorgnette::nerf
