// The analytic sphere's training views (synthetic_scene.h) with a model sized for them
// (choose_model_size), as the NeRF tests that train or update a small model set them up.
#pragma once
#include <cstdint>

#include "host/cl/runtime.h"
#include "host/nerf/model.h"
#include "host/nerf/sizing.h"
#include "synthetic_scene.h"

namespace lorgnette::nerf::nerftest {

struct SphereModelScene {
  // `views` ring cameras at distance 2.2 of `size` x `size` pixels; models with a batch of
  // `batch` samples and seed `seed`.
  SphereModelScene(int views, int size, uint32_t batch = 1u << 12, uint32_t seed = 7)
      : train(render_views(ring_cameras(views, 2.2f, size))),
        sizing(choose_model_size(train.views, SizingOverrides{})),
        batch(batch),
        seed(seed) {}

  NerfModel make_model() {
    return NerfModel(rt, sizing.field, sizing.aabb, sizing.occupancy_resolution, sizing.step, batch, seed,
                     true);
  }

  cl::Runtime rt{cl::RuntimeOptions{"", "", false}};
  SceneViews train;
  ModelSizing sizing;
  uint32_t batch, seed;
};

}  // namespace lorgnette::nerf::nerftest
