// The ear search's pairing rules (fit/ear_pairing.h), each on made-up lines with known answers: the
// veto and the height allowed under hair, the pair that agrees, one height, the shared rest and the
// fragment's depth, the mirrored side. Scene units are mm here; y up, z forward.
#include "fit/ear_pairing.h"

#include <gtest/gtest.h>

namespace lorgnette::fit {
namespace {

// A found line whose rest lies at (x, height, depth), `slices` depths long.
EarRootSide line(double x, double height, double depth, int slices = 10) {
  EarRootSide s;
  s.found = true, s.point = {x, height, depth}, s.height_mm = height, s.depth_mm = depth, s.slices = slices;
  s.lateral_mm = 3.0;
  return s;
}

const EarPairFrame kFrame{{0, 1, 0}, {0, 0, 1}, 1.0};

TEST(EarPairing, TheVetoLeavesTheHighestLineItAccepts) {
  const EarPairOptions o;
  const EarVeto above_12_is_hair = [](const EarRootSide& s) {
    return s.height_mm > 12.0 ? std::string("hair") : std::string();
  };
  std::vector<EarRootSide> lines = accepted_lines({line(70, 18, 0), line(70, 9, -5)}, above_12_is_hair, o);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].height_mm, 9.0);
  EXPECT_EQ(lines[0].higher_vetoed, 1);
  // No veto: both lines, in order.
  EXPECT_EQ(accepted_lines({line(70, 18, 0), line(70, 9, -5)}, {}, o).size(), 2u);
}

TEST(EarPairing, UnderAnotherLineALineLiesWhereEarsDo) {
  const EarPairOptions o;  // plausible_highest_mm 20
  // The first line may lie high (it has no line above it); one under it at 22 mm may not.
  const std::vector<EarRootSide> lines = accepted_lines({line(70, 25, 0), line(70, 22, -5)}, {}, o);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].height_mm, 25.0);
  // Every line refused: the side is vetoed, saying why for the first and the next.
  const std::vector<EarRootSide> none = accepted_lines(
      {line(70, 25, 0), line(70, 22, -5)},
      [](const EarRootSide& s) { return s.height_mm > 24 ? "hair" : ""; }, o);
  ASSERT_EQ(none.size(), 1u);
  EXPECT_FALSE(none[0].found);
  EXPECT_TRUE(none[0].vetoed);
  EXPECT_EQ(none[0].why.rfind("hair (a crease +25.0 mm above the eye corner", 0), 0u) << none[0].why;
  EXPECT_NE(none[0].why.find("the 1 lower line(s) of creases too (the highest: it lies under hair"),
            std::string::npos)
      << none[0].why;
  // A side not found stays as it is.
  EarRootSide missing;
  missing.why = "no crease";
  EXPECT_EQ(accepted_lines({missing}, {}, o).at(0).why, "no crease");
}

TEST(EarPairing, APairThatAgreesRanksHighestTogetherThenClosest) {
  const EarPairOptions o;  // 15 mm in height, 12 in depth
  // Left: the first line over the ear's back (-30), then the root (-12), then another at -10.
  const std::vector<EarRootSide> lefts = {line(70, 16, -30), line(70, 9, -12), line(70, 8, -10)};
  const std::vector<EarRootSide> rights = {line(-70, 10, -11), line(-70, 9, -30)};
  // (0, 1) and (1, 0) both agree at rank 1 (their places' sum): the closer in depth, (0, 1) at 0 mm
  // against 1 mm, is used.
  std::optional<EarLinePair> p = agreeing_pair(lefts, rights, kFrame, o, 5);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->left, 0u);
  EXPECT_EQ(p->right, 1u);
  // A stand-in must span short_line_slices depths: the right's second line too short, the left's root.
  std::vector<EarRootSide> short_rights = rights;
  short_rights[1].slices = 4;
  p = agreeing_pair(lefts, short_rights, kFrame, o, 5);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->left, 1u);
  EXPECT_EQ(p->right, 0u);
  // No other pair agrees: none.
  EXPECT_FALSE(agreeing_pair({lefts[0]}, {rights[0]}, kFrame, o, 5));
}

TEST(EarPairing, TwoEarsLieAtOneHeight) {
  const EarPairOptions o;
  EXPECT_EQ(height_gap_refusal(line(70, 10, 0), line(-70, -4, 0), kFrame, o), "");
  const std::string why = height_gap_refusal(line(70, 10, 0), line(-70, -6, 0), kFrame, o);
  EXPECT_EQ(why.rfind("the two sides' rests lie 16.0 mm apart in height (over 15", 0), 0u) << why;
}

TEST(EarPairing, TheSharedRestIsTheMeanUnlessOneLineIsAFragment) {
  std::string note;
  const Eigen::Vector3d mid = shared_rest(line(70, 10, -10), line(-70, 6, -16), kFrame, 5, note);
  EXPECT_LT((mid - Eigen::Vector3d(0, 8, -13)).norm(), 1e-12);
  EXPECT_EQ(note, "");
  // The left line 4 depths long opposite a whole one: the depth is the right's, the height the mean.
  const Eigen::Vector3d frag = shared_rest(line(70, 10, -25, 4), line(-70, 6, -16), kFrame, 5, note);
  EXPECT_LT((frag - Eigen::Vector3d(0, 8, -16)).norm(), 1e-12);
  EXPECT_EQ(note, "the left side's line holds 4 depths: the rests' depth is the right side's");
  // Both short, or both long: the mean.
  EXPECT_LT((shared_rest(line(70, 10, -25, 4), line(-70, 6, -16, 3), kFrame, 5, note) -
             Eigen::Vector3d(0, 8, -20.5))
                .norm(),
            1e-12);
}

TEST(EarPairing, AMirroredRestLiesAtTheFoundOnesHeightAndDepth) {
  const EarRootSide found = line(73, 10, -14);  // 3 mm outside its temple
  const Eigen::Vector3d other = mirrored_rest(found, {-70, -5, 12}, {-1, 0, 0}, kFrame);
  EXPECT_LT((other - Eigen::Vector3d(-73, 10, -14)).norm(), 1e-12);
  // level: the height and depth of the target, the width of the point.
  EXPECT_LT((kFrame.level({1, 2, 3}, {7, 8, 9}) - Eigen::Vector3d(1, 8, 9)).norm(), 1e-12);
}

}  // namespace
}  // namespace lorgnette::fit
