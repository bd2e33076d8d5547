// The default training budget in steps (see train_budget.h).
#include "host/nerf/train_budget.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace lorgnette::nerf {

StepBudget default_training_steps(uint64_t parameters, uint32_t batch_log2, double samples_per_parameter,
                                  uint64_t min_steps) {
  const double batch = std::ldexp(1.0, int(batch_log2));
  const double raw = samples_per_parameter * double(parameters) / batch;
  // Round to whole hundreds so the number reads as a setting, not a measurement.
  uint64_t steps = uint64_t(std::llround(raw / 100.0)) * 100;
  steps = std::clamp<uint64_t>(steps, min_steps, kMaxSteps);
  StepBudget b;
  b.steps = steps;
  b.why =
      fmt::format("{} steps of 2^{} samples: {:.0f} samples for each of the model's {:.1f} M parameters{}",
                  steps, batch_log2, samples_per_parameter, double(parameters) / 1e6,
                  raw < double(min_steps)   ? fmt::format(", raised to the minimum {}", min_steps)
                  : raw > double(kMaxSteps) ? fmt::format(", capped at {}", kMaxSteps)
                                            : std::string());
  return b;
}

std::string describe_budget(uint64_t steps, double seconds, bool defaulted, const std::string& default_why) {
  if (defaulted) return "default budget: " + default_why;
  if (steps > 0) return fmt::format("{} steps (given)", steps);
  return fmt::format("{:g} s of wall-clock time (given; the step count depends on the device)", seconds);
}

}  // namespace lorgnette::nerf
