// When the opacity prior and the room-explained clearing start (BackgroundOptions::opacity_prior_start,
// train --prior-start; nerf::opacity_prior_share): the share of the prior's weight at each step. The
// kernels' clearing pulls the ray's opacity, so it clears a haze only while it is partly transparent
// (tests/host/nerf/solid_prior_test.cpp pins that on an analytic ray); the start decides how much of
// the haze of the first steps is still partly transparent when it comes (docs/room-training.md, "The
// opacity prior and the room-explained clearing").
#include <gtest/gtest.h>

#include "host/nerf/background_field.h"

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

}  // namespace
}  // namespace lorgnette::nerf
