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
// steps (6.1 M parameters); docs/bench/real-captures.md has the face PSNR against the 2^19 runs.
inline constexpr uint32_t kRoomCaptureMaxLog2Table = 18;
// And train kRoomCaptureSamplesPerParameter samples per parameter instead of kSamplesPerParameter,
// from the CPU seconds of in2n-face's runs (x 463 / 839, the 2^19 default's quiet wall per CPU s):
// 2300 steps (25) 487 CPU s, about 270 s quiet, face PSNR 24.89 dB; 1800 (19) 414 CPU s, about
// 229 s, 24.79 dB; 1600 (17) 356 CPU s, about 197 s, 24.71 dB (the 2^19 default: 24.49 dB). With the
// ~13 s fit only 17 keeps a real capture to a fitted try-on within 4 minutes with a margin.
inline constexpr double kRoomCaptureSamplesPerParameter = 17.0;
// And at least kRoomCaptureMinSteps steps: separating the subject from the room takes optimizer
// steps, not only samples. On an NVIDIA H200 (2^18 samples per step, so the rule above gives 400 for
// a 5.5 M-parameter room capture and the old minimum 500 applied) the procedural head in room 1
// (+-40 deg) leaked 2.72 % of the subject's area after 500 steps, 1.89 % after 1000 and 1.81 % after
// 1500 (8.7, 18.3 and 27.7 s); 1200 steps of 2^16 on the CPU leak 1.7-1.8 %. The 2-core CPU's
// budget (2^16: 1400-1600 steps) is above this minimum and unchanged.
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
