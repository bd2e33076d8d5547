// Holes in a render's head interior (host/render/hole_eval.h) on an analytic subject: a head disc
// (radius 30 px) on a body rectangle below it, the render's opacity equal to the matte. Whole, no
// interior pixel is a hole; a square punched through the head's middle is counted pixel for pixel;
// one at the matte's edge (inside its 7 px erosion) and one in the body below the upper 45 % of the
// subject's rows are not judged.
#include "host/render/hole_eval.h"

#include <gtest/gtest.h>

namespace lorgnette::render {
namespace {

constexpr int kW = 160, kH = 200, kCx = 80, kCy = 50, kR = 30;

struct Subject {
  Image matte{kW, kH, 1}, pred{kW, kH, 4};
  Subject() {
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const bool head = (x - kCx) * (x - kCx) + (y - kCy) * (y - kCy) <= kR * kR;
        const bool body = y >= 75 && y < kH && x >= 30 && x < 130;
        matte.at(x, y, 0) = head || body ? 1.0f : 0.0f;
        pred.at(x, y, 3) = matte.at(x, y, 0);
      }
  }
  void punch(int x0, int y0, int side) {
    for (int y = y0; y < y0 + side; ++y)
      for (int x = x0; x < x0 + side; ++x) pred.at(x, y, 3) = 0.2f;
  }
};

TEST(HoleEval, WholeSubjectHasNoHoles) {
  Subject s;
  const InteriorHoles r = head_interior_holes(s.pred, s.matte);
  // Rows 20..199 are the subject's; the upper 45 % are rows 20..100 (81 rows): the head disc and the
  // body's top, both eroded by 7 px.
  EXPECT_GT(r.interior_pixels, 2000);
  EXPECT_EQ(r.holes, 0);
  EXPECT_EQ(r.share, 0.0);
}

TEST(HoleEval, PunchedHeadIsCountedEdgeAndBodyAreNot) {
  Subject s;
  const long interior = head_interior_holes(s.pred, s.matte).interior_pixels;
  s.punch(kCx - 5, kCy - 5, 10);  // 100 px in the head's middle
  InteriorHoles r = head_interior_holes(s.pred, s.matte);
  EXPECT_EQ(r.interior_pixels, interior);
  EXPECT_EQ(r.holes, 100);
  EXPECT_NEAR(r.share, 100.0 / double(interior), 1e-12);
  Subject edge;
  edge.punch(kCx + kR - 5, kCy - 2, 5);  // within 7 px of the head's outline
  EXPECT_EQ(head_interior_holes(edge.pred, edge.matte).holes, 0);
  Subject body;
  body.punch(60, 150, 20);  // the body, below the upper 45 % of the rows
  EXPECT_EQ(head_interior_holes(body.pred, body.matte).holes, 0);
  // An empty matte has no interior.
  Image none(kW, kH, 1);
  EXPECT_EQ(head_interior_holes(s.pred, none).interior_pixels, 0);
}

}  // namespace
}  // namespace lorgnette::render
