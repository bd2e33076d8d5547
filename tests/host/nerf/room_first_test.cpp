// The room model first (BackgroundOptions::room_first, host/nerf/background_field.h) on the analytic
// sphere before a plain wall: the room trains alone on the rays that miss the subject's box, so at
// the subject's first step the wall around it is already explained (that step's loss, mostly wall
// pixels, falls far below the loss of a training without it); where the wall has the colour of the
// subject's skin, those rays teach the room nothing and the first step's loss stays near that of a
// training without the room first.
#include <gtest/gtest.h>

#include "host/nerf/sizing.h"
#include "host/nerf/trainer.h"
#include "synthetic_scene.h"

namespace {

using namespace lorgnette;
using namespace lorgnette::nerf;

constexpr float kWall[3] = {0.6f, 0.5f, 0.3f};  // linear RGB

struct Scene {
  cl::Runtime rt{cl::RuntimeOptions{"", "", false}};
  // Sized on the sphere's own alpha (its box leaves a ring of each view on the wall alone), trained on
  // the sphere over the opaque wall, as a mask-less capture shows it.
  nerftest::SceneViews cut = nerftest::render_views(nerftest::ring_cameras(12, 2.2f, 48));
  ModelSizing sizing = choose_model_size(cut.views, SizingOverrides{});
  std::vector<Image> images;
  std::vector<View> views;

  Scene() {
    for (const Image& im : cut.images) {
      Image opaque = im;
      for (int y = 0; y < im.height; ++y)
        for (int x = 0; x < im.width; ++x) {
          const float a = im.at(x, y, 3);
          for (int k = 0; k < 3; ++k) opaque.at(x, y, k) = a * im.at(x, y, k) + (1.0f - a) * kWall[k];
          opaque.at(x, y, 3) = 1.0f;
        }
      images.push_back(std::move(opaque));
    }
    for (size_t i = 0; i < images.size(); ++i) views.push_back(View{cut.views[i].camera, &images[i]});
  }

  // The loss of the subject's first step after `room_first` steps of the room alone.
  double first_loss(uint32_t room_first, const std::vector<std::array<float, 2>>& skin = {}) {
    NerfModel model(rt, sizing.field, sizing.aabb, sizing.occupancy_resolution, sizing.step, 1u << 12, 7,
                    true);
    TrainOptions o;
    o.steps = 1;
    o.seed = 7;
    o.progress = false;
    o.snapshot_every_seconds = 0.0;
    o.background.enabled = true;
    o.background.log2_table = 12;
    o.background.levels = 6;
    o.background.room_first = room_first;
    if (!skin.empty()) {
      o.background.subject = SubjectZones{};
      o.background.subject->skin.chroma = skin;
    }
    TrainResult r = Trainer(model, views, o, sizing.occupancy_mask).run();
    EXPECT_EQ(r.loss_curve.size(), 1u);
    return r.loss_curve.empty() ? 0.0 : r.loss_curve.front();
  }
};

TEST(RoomFirst, TheWallAroundTheSubjectIsExplainedBeforeItsFirstStep) {
  Scene s;
  const double without = s.first_loss(0), with = s.first_loss(64);
  // Measured: 0.0111 without, 0.0038 with (sRGB MSE of the first batch, most of its rays on the
  // wall).
  EXPECT_GT(without, 0.005);
  EXPECT_LT(with, 0.5 * without);
}

TEST(RoomFirst, AWallOfTheSkinsColourWaitsForTheSubject) {
  Scene s;
  const float sum = kWall[0] + kWall[1] + kWall[2];
  const double without = s.first_loss(0), skin_wall = s.first_loss(64, {{kWall[0] / sum, kWall[1] / sum}});
  // No ray taught the room (every wall pixel may be skin): the first step sees the untaught room,
  // whose occupancy updates alone moved it (measured 0.0104 against 0.0111; taught: 0.0038).
  EXPECT_GT(skin_wall, 0.8 * without);
}

}  // namespace
