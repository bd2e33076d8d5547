// A stop request (Ctrl-C, SIGTERM) ends a fit at its next rendered view: the fit has nothing to save,
// and `fit` used to render all its views (over three minutes at --resolution 1024) after SIGTERM.
// The same view renders once the request is cleared, so the refusal is the request's doing.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "fit/nerf_view_source.h"
#include "fit/view_planning.h"
#include "host/nerf/model.h"
#include "host/util/interrupt.h"

namespace lorgnette::fit {
namespace {

TEST(FitInterrupt, AStopRequestEndsTheFitAtTheNextView) {
  cl::Runtime rt({"", "", false});
  field::FieldConfig config;
  config.log2_table_size = 10;
  config.finest_resolution = 32;
  nerf::NerfModel model(rt, config, {{-1, -1, -1}, {1, 1, 1}}, 16, 0.01f, 256, 1, true);
  NerfViewSource source(model, ViewPrior{});
  Orbit o;
  o.width = o.height = 16;
  o.distance = 4.0;
  const Camera cam = orbit_camera(o, 0.0, 0.0);
  request_interrupt();
  std::string message;
  try {
    source.render(cam);
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  clear_interrupt();
  EXPECT_NE(message.find("interrupted"), std::string::npos) << message;
  const Image view = source.render(cam);
  EXPECT_EQ(view.width, 16);
  EXPECT_EQ(view.height, 16);
}

}  // namespace
}  // namespace lorgnette::fit
