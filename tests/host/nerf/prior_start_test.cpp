// When the opacity prior and the room-explained clearing start (BackgroundOptions::opacity_prior_start,
// nerf::opacity_prior_share): the share of the prior's weight at each step, and the default's rule.
// The kernels' clearing pulls the ray's opacity, so it clears a haze only while it is partly
// transparent (tests/host/nerf/solid_prior_test.cpp pins that on an analytic ray); the default
// start makes it act within the occupancy grid's warm-up, in which the pale captures' haze forms
// (docs/room-training.md, "The opacity prior and the room-explained clearing").
#include <gtest/gtest.h>

#include "host/nerf/background_field.h"
#include "host/nerf/occupancy_update.h"

namespace lorgnette::nerf {
namespace {

TEST(PriorStart, TheShareRampsInFromTheStartStep) {
  BackgroundOptions o;
  o.opacity_prior_start = 100, o.opacity_prior_ramp = 200;
  EXPECT_FLOAT_EQ(opacity_prior_share(o, 0), 0.0f);
  EXPECT_FLOAT_EQ(opacity_prior_share(o, 100), 0.0f);
  EXPECT_FLOAT_EQ(opacity_prior_share(o, 150), 0.25f);
  EXPECT_FLOAT_EQ(opacity_prior_share(o, 300), 1.0f);
  EXPECT_FLOAT_EQ(opacity_prior_share(o, 100000), 1.0f);
  o.opacity_prior_ramp = 0;  // a step at the start
  EXPECT_FLOAT_EQ(opacity_prior_share(o, 99), 0.0f);
  EXPECT_FLOAT_EQ(opacity_prior_share(o, 101), 1.0f);
}

// Not from step 0 (the still transparent subject would be pushed to clear), and a quarter or more of
// the weight by the warm-up's end: from there on (the previous start) the haze of the pale captures
// had become opaque where the room model had not yet learnt the wall, and stayed.
TEST(PriorStart, TheDefaultActsWithinTheOccupancyWarmUp) {
  const BackgroundOptions o;
  const uint32_t warmup = OccupancyOptions{}.warmup_steps;
  EXPECT_FLOAT_EQ(opacity_prior_share(o, 0), 0.0f);
  EXPECT_GT(o.opacity_prior_start, 0u);
  EXPECT_LT(o.opacity_prior_start, warmup);
  EXPECT_GE(opacity_prior_share(o, warmup), 0.25f);
}

}  // namespace
}  // namespace lorgnette::nerf
