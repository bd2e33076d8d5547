// Matte scores (host/render/matte_eval.h) on an analytic scene: a disc whose anti-aliased matte is
// its exact coverage of each pixel (16 x 16 samples), against predictions whose scores follow by
// hand: the matte itself, the disc thresholded at the pixel centres, and a uniform haze over the
// room. The region rule (matte pixels whose subject point lies outside the model's box are not
// judged) is checked with a depth map that puts one strip of the disc far outside the box; the face
// PSNRs with a face hull larger than the disc, whose rim is room.
#include "host/render/matte_eval.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "host/render/orbit.h"
#include "host/util/image_io.h"

namespace {

using namespace lorgnette;
constexpr int kW = 64, kH = 48;
constexpr float kCx = 30.3f, kCy = 22.7f, kR = 13.4f;  // the disc, in pixels (off the pixel grid)

float disc_coverage(int x, int y) {
  int in = 0;
  for (int sy = 0; sy < 16; ++sy)
    for (int sx = 0; sx < 16; ++sx) {
      const float u = x + (sx + 0.5f) / 16.0f - kCx, v = y + (sy + 0.5f) / 16.0f - kCy;
      in += u * u + v * v <= kR * kR;
    }
  return float(in) / 256.0f;
}

struct Scene {
  Camera camera = render::look_at({0, 0, 3}, {0, 0, 0}, {0, 1, 0}, kW, kH, 30.0f);
  Image matte{kW, kH, 1}, truth{kW, kH, 3, 0.5f};
  nerf::Aabb box;  // [-1, 1]^3: the camera's rays meet it about 3 units away
  Scene() {
    box.min = {-1, -1, -1}, box.max = {1, 1, 1};
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) matte.at(x, y, 0) = disc_coverage(x, y);
  }
  render::MatteScore score(const Image& pred, const Image* depth = nullptr) const {
    return render::score_matte({camera, &pred, &truth, &matte, depth, {}}, box);
  }
};

Image rgba_with_alpha(const Scene& s, float (*alpha)(float m)) {
  Image pred(kW, kH, 4);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) pred.at(x, y, 3) = alpha(s.matte.at(x, y, 0));
  return pred;
}

TEST(MatteEval, LeakBeyondTheMatteIsZeroForARenderEqualToTheAntiAliasedMatte) {
  Scene s;
  double outline = 0.0;  // sum m (1 - m): what the product-form leak charges the exact matte
  long subject = 0, aa = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const double m = s.matte.at(x, y, 0);
      outline += m * (1.0 - m), subject += m >= 0.5, aa += m > 0.0 && m < 1.0;
    }
  ASSERT_GT(aa, 60);  // the disc's outline has anti-aliased pixels all round
  const render::MatteScore r = s.score(rgba_with_alpha(s, [](float m) { return m; }));
  EXPECT_EQ(r.subject_pixels, subject);
  EXPECT_DOUBLE_EQ(r.iou, 1.0);
  EXPECT_NEAR(r.leak, outline / double(subject), 1e-9);
  EXPECT_GT(r.leak, 0.01);  // 2 pi R / (pi R^2) ~ 0.15 of a pixel's worth per outline pixel
  EXPECT_NEAR(r.leak_excess, 0.0, 1e-12);
}

TEST(MatteEval, ThresholdedDiscAndHazeScoreWhatTheyAddBeyondTheMatte) {
  Scene s;
  long subject = 0, room = 0;
  double beyond = 0.0;  // the thresholded disc's opacity beyond the matte: sum over m >= 0.5 of 1 - m
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const double m = s.matte.at(x, y, 0);
      subject += m >= 0.5, room += m == 0.0;
      if (m >= 0.5) beyond += 1.0 - m;
    }
  const render::MatteScore sharp =
      s.score(rgba_with_alpha(s, [](float m) { return m >= 0.5f ? 1.0f : 0.0f; }));
  EXPECT_DOUBLE_EQ(sharp.iou, 1.0);
  EXPECT_NEAR(sharp.leak_excess, beyond / double(subject), 1e-9);
  EXPECT_NEAR(sharp.leak, sharp.leak_excess, 1e-9);  // a in {0, 1}: a (1 - m) = max(0, a - m)

  // The exact matte plus 0.1 of opacity on every pure room pixel: both leaks grow by 0.1 x room.
  const render::MatteScore exact = s.score(rgba_with_alpha(s, [](float m) { return m; }));
  const render::MatteScore hazy = s.score(rgba_with_alpha(s, [](float m) { return m == 0.0f ? 0.1f : m; }));
  const double haze = 0.1 * double(room) / double(subject);
  EXPECT_NEAR(hazy.leak - exact.leak, haze, 1e-6);
  EXPECT_NEAR(hazy.leak_excess, haze, 1e-6);
  EXPECT_DOUBLE_EQ(hazy.iou, 1.0);  // 0.1 < 0.5 everywhere in the room
}

TEST(MatteEval, SubjectOutsideTheModelsBoxIsNotJudged) {
  Scene s;
  const float inf = std::numeric_limits<float>::infinity();
  Image depth(kW, kH, 1, inf);
  long strip = 0, subject = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const bool t = s.matte.at(x, y, 0) >= 0.5f;
      subject += t;
      // The disc's lower rows lie 100 units away (far outside the box), the rest 3 units (inside).
      if (t) depth.at(x, y, 0) = y >= 30 ? 100.0f : 3.0f;
      strip += t && y >= 30;
    }
  ASSERT_GT(strip, 50);
  // Opacity only inside the box's part of the disc: the missing strip costs nothing.
  Image pred(kW, kH, 4);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < kW; ++x) pred.at(x, y, 3) = s.matte.at(x, y, 0) >= 0.5f ? 1.0f : 0.0f;
  const render::MatteScore r = s.score(pred, &depth);
  EXPECT_EQ(r.subject_pixels, subject - strip);
  EXPECT_DOUBLE_EQ(r.iou, 1.0);
  // Without the depth map the strip is judged: missed subject pixels lower the IoU.
  const render::MatteScore all = s.score(pred);
  EXPECT_EQ(all.subject_pixels, subject);
  EXPECT_NEAR(all.iou, double(subject - strip) / double(subject), 1e-12);
}

TEST(MatteEval, FacePsnrOverTheSubjectLeavesTheHullsRoomOut) {
  Scene s;
  // Face points on the rays through the integer pixel positions (10, 5) .. (52, 42), 3 units out:
  // their hull is that pixel rectangle, which holds the whole disc and a rim of room around it.
  const int x0 = 10, y0 = 5, x1 = 52, y1 = 42;
  std::vector<Eigen::Vector3f> face;
  const LgnVec3 o = camera_origin(&s.camera);
  for (auto [u, v] : {std::pair{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}) {
    const LgnVec3 d = camera_ray_dir(&s.camera, float(u), float(v));
    face.emplace_back(o.x + 3.0f * d.x, o.y + 3.0f * d.y, o.z + 3.0f * d.z);
  }
  // The prediction: linear 0.6 where the disc covers the pixel fully (the truth is 0.5), white
  // elsewhere (a model that renders the room clear over a white background).
  Image pred(kW, kH, 4, 1.0f);
  long in = 0, rim = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const bool full = s.matte.at(x, y, 0) >= 0.999f;
      if (full)
        for (int c = 0; c < 3; ++c) pred.at(x, y, c) = 0.6f;
      if (x >= x0 && x <= x1 && y >= y0 && y <= y1) (full ? in : rim) += 1;
    }
  ASSERT_GT(in, 400);
  ASSERT_GT(rim, 600);
  const render::MatteScore r =
      render::score_matte({s.camera, &pred, &s.truth, &s.matte, nullptr, face}, s.box);
  const double e_in = linear_to_srgb(0.6f) - linear_to_srgb(0.5f), e_rim = 1.0 - linear_to_srgb(0.5f);
  EXPECT_EQ(r.face_pixels, in + rim);
  EXPECT_EQ(r.face_subject_pixels, in);
  // float sRGB conversions: 1e-4 dB.
  EXPECT_NEAR(r.face_psnr_subject, -10.0 * std::log10(e_in * e_in), 1e-4);
  EXPECT_NEAR(r.face_psnr, -10.0 * std::log10((in * e_in * e_in + rim * e_rim * e_rim) / double(in + rim)),
              1e-4);
  EXPECT_GT(r.face_psnr_subject - r.face_psnr, 5.0);  // the rim's room dominates the whole hull
}

}  // namespace
