// The hybrid-frame adapter of a surface pass (mesh/frame_surfaces.h): its callbacks give the pass's
// own screen rectangle and buffers (bit for bit, at the samples per pixel the frame asks for, with
// the caller's other settings), they keep the pass alive after its owner lets it go, and a null pass
// is refused.
#include "mesh/frame_surfaces.h"

#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>

namespace lorgnette::mesh {
namespace {

// A small white triangle 1 unit in front of a 64x48 camera, well inside the image, so its screen
// rectangle is a strict part of the frame and its edge pixels are partly covered.
std::shared_ptr<const SurfacePass> triangle_pass() {
  TriMesh m;
  m.positions = {{-0.1f, -0.1f, -1.0f}, {0.1f, -0.05f, -1.0f}, {0.0f, 0.12f, -1.0f}};
  m.triangles = {{0, 1, 2}};
  m.triangle_material = {0};
  m.triangle_part = {0};
  Material white;
  white.name = "white";
  white.base_color = {1, 1, 1};
  m.materials = {white};
  m.part_names = {"triangle"};
  return std::make_shared<const SurfacePass>(m, Eigen::Matrix4f::Identity());
}

Camera camera() { return look_at_camera({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 60.0f, 64, 48); }

bool same_bits(const SurfaceBuffers& a, const SurfaceBuffers& b) {
  auto eq = [](const std::vector<float>& x, const std::vector<float>& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(float)) == 0;
  };
  return a.width == b.width && a.height == b.height && eq(a.color_alpha, b.color_alpha) &&
         eq(a.depth, b.depth) && eq(a.filter, b.filter);
}

TEST(FrameSurfaces, ScreenRectIsThePassOwn) {
  auto pass = triangle_pass();
  GlassesSurfaces g = frame_surfaces(pass);
  std::array<int, 4> want = pass->screen_rect(camera());
  std::array<uint32_t, 4> got = g.screen_rect(camera());
  for (int i = 0; i < 4; ++i) EXPECT_EQ(got[i], uint32_t(want[i])) << "corner " << i;
  EXPECT_GT(want[0], 0);  // a strict part of the image: the test would not tell a whole-image rect
  EXPECT_LT(want[2], 64);
}

TEST(FrameSurfaces, RenderIsThePassAtTheFrameSamplesPerPixel) {
  auto pass = triangle_pass();
  SurfaceParams base;
  base.seed = 7;
  base.threads = 1;
  base.samples_per_pixel = 2;  // overridden by each frame's choice
  GlassesSurfaces g = frame_surfaces(pass, base);
  for (uint32_t spp : {1u, 9u}) {
    SurfaceParams p = base;
    p.samples_per_pixel = int(spp);
    EXPECT_TRUE(same_bits(g.render(camera(), spp), pass->render(camera(), p))) << spp << " spp";
  }
  // The choice matters on this scene (partly covered edge pixels), so the checks above could fail.
  SurfaceParams one = base, nine = base;
  one.samples_per_pixel = 1;
  nine.samples_per_pixel = 9;
  EXPECT_FALSE(same_bits(pass->render(camera(), one), pass->render(camera(), nine)));
}

TEST(FrameSurfaces, CallbacksKeepThePassAlive) {
  auto pass = triangle_pass();
  std::weak_ptr<const SurfacePass> watch = pass;
  SurfaceBuffers want = pass->render(camera(), SurfaceParams{});
  GlassesSurfaces g = frame_surfaces(std::move(pass));
  pass.reset();
  ASSERT_FALSE(watch.expired());
  EXPECT_TRUE(same_bits(g.render(camera(), 4), want));
  g = GlassesSurfaces{};
  EXPECT_TRUE(watch.expired());
}

TEST(FrameSurfaces, NullPassIsRefused) { EXPECT_THROW(frame_surfaces(nullptr), std::invalid_argument); }

}  // namespace
}  // namespace lorgnette::mesh
