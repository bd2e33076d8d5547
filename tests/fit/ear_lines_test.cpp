// The ear search's line finder (fit/ear_lines.h) on made-up profiles and creases with known answers:
// the crease where a steep skull side turns onto a flat ear top, and the shapes that are not one; lines
// traced across depths; their order; each line's rest.
#include "fit/ear_lines.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lorgnette::fit {
namespace {

// A profile sampled every 1 mm from 0 to 30 mm out: a skull side falling at `inner_deg` down to the
// crease at 12 mm and `crease_mm` high, then at `outer_deg` beyond it.
std::vector<double> laterals() {
  std::vector<double> x;
  for (int i = 0; i <= 30; ++i) x.push_back(i);
  return x;
}
std::vector<double> profile(double inner_deg, double outer_deg, double crease_mm = 8.0) {
  std::vector<double> h;
  for (double x : laterals()) {
    const double slope = std::tan((x < 12.0 ? inner_deg : outer_deg) * M_PI / 180.0);
    h.push_back(crease_mm + (x - 12.0) * slope);
  }
  return h;
}

TEST(EarLines, TheCreaseIsWhereTheSkullsSideTurnsOntoTheEarsTop) {
  const EarCreaseOptions o;
  const EarCrease c = find_crease(profile(-70.0, 0.0), laterals(), 3, o);
  ASSERT_TRUE(c.found);
  EXPECT_DOUBLE_EQ(c.lateral_mm, 12.0);
  EXPECT_NEAR(c.height_mm, 8.0, 1e-12);
  EXPECT_NEAR(c.bend_deg, 70.0, 1e-9);
  EXPECT_NEAR(c.top_mm, 8.0, 1e-12);  // the ear's flat top 3 samples outside
}

TEST(EarLines, TheEarsTopRunsOutwardsUntilItFallsOff) {
  const EarCreaseOptions o;
  // A flat top 3 mm wide past the crease's own span (12 + 3 .. 18 mm), then the ear's outer side
  // falling at 75 deg: the top holds 15, 16, 17 and 18 mm out, not the outer side.
  std::vector<double> h = profile(-70.0, 0.0);
  for (size_t i = 19; i < h.size(); ++i) h[i] = h[18] - (double(i) - 18.0) * std::tan(75.0 * M_PI / 180.0);
  EarCrease c = find_crease(h, laterals(), 3, o);
  ASSERT_TRUE(c.found);
  ASSERT_EQ(c.top.size(), 4u);
  for (size_t k = 0; k < 4; ++k) EXPECT_EQ(c.top[k], Eigen::Vector2d(15.0 + double(k), 8.0));
  // Falling off 1 mm past the crease's span: the top is that one point.
  for (size_t i = 16; i < h.size(); ++i) h[i] = h[15] - (double(i) - 15.0) * std::tan(75.0 * M_PI / 180.0);
  c = find_crease(h, laterals(), 3, o);
  ASSERT_TRUE(c.found);
  ASSERT_EQ(c.top.size(), 1u);
  EXPECT_EQ(c.top[0], Eigen::Vector2d(15.0, 8.0));
  // A top that goes on: at most `span` samples past the first.
  c = find_crease(profile(-70.0, 10.0), laterals(), 3, o);
  ASSERT_TRUE(c.found);
  ASSERT_EQ(c.top.size(), 4u);
  EXPECT_NEAR(c.top.back().y(), 8.0 + 6.0 * std::tan(10.0 * M_PI / 180.0), 1e-12);
}

TEST(EarLines, NotACrease) {
  const EarCreaseOptions o;
  // Slopes over one sample, so that only the crease's own sample bends: too gentle a bend; an inside
  // too flat (hair, a NeRF's inside); a rising outside (a wall); an outside that falls away (an edge);
  // a crease above the band where ears lie.
  ASSERT_TRUE(find_crease(profile(-70.0, 0.0), laterals(), 1, o).found);
  EXPECT_FALSE(find_crease(profile(-50.0, -35.0), laterals(), 1, o).found);
  EXPECT_FALSE(find_crease(profile(-40.0, 0.0), laterals(), 1, o).found);
  EXPECT_FALSE(find_crease(profile(-70.0, 40.0), laterals(), 1, o).found);
  EXPECT_FALSE(find_crease(profile(-80.0, -65.0), laterals(), 1, o).found);
  EXPECT_FALSE(find_crease(profile(-70.0, 0.0, o.highest_mm + 2.0), laterals(), 1, o).found);
  // A miss next to the crease hides it.
  std::vector<double> h = profile(-70.0, 0.0);
  h[13] = std::nan("");
  EXPECT_FALSE(find_crease(h, laterals(), 1, o).found);
}

EarCrease at(double lateral, double height) { return {true, lateral, height, 40.0, height, {}}; }

TEST(EarLines, CreasesThatContinueEachOtherMakeALine) {
  // Depths 0-3 one line (steps within 5 mm), a jump of 6 mm in height at 4, a gap at 6.
  const std::vector<EarCrease> creases = {at(10, 8),  at(11, 9),  at(11, 14), at(12, 9),
                                          at(12, 15), at(13, 16), {},         at(12, 9)};
  const std::vector<EarCreaseLine> lines = trace_crease_lines(creases, 5.0);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0].start, 0);
  EXPECT_EQ(lines[0].len, 4);
  EXPECT_EQ(lines[1].start, 4);
  EXPECT_EQ(lines[1].len, 2);
  EXPECT_EQ(lines[2].start, 7);
  EXPECT_EQ(lines[2].len, 1);
  // Medians of three: the 14 mm spike is smoothed away; at the ends, the end and the two inside it.
  EXPECT_EQ(lines[0].smooth, (std::vector<double>{9, 9, 9, 9}));
  EXPECT_DOUBLE_EQ(lines[0].top, 9.0);
  EXPECT_DOUBLE_EQ(lines[1].top, 16.0);  // (two creases: the higher)
}

TEST(EarLines, AShortLineAboveALongOneFollowsIt) {
  std::vector<EarCreaseLine> lines(3);
  lines[0].len = 3, lines[0].top = 18.0;  // hair's edge
  lines[1].len = 8, lines[1].top = 10.0;  // the root
  lines[2].len = 6, lines[2].top = 4.0;
  order_crease_lines(lines, 5);
  EXPECT_EQ(lines[0].len, 8);
  EXPECT_EQ(lines[1].len, 3);
  EXPECT_EQ(lines[2].len, 6);
  order_crease_lines(lines, 1);  // every line long enough: by height
  EXPECT_EQ(lines[0].len, 3);
  EXPECT_EQ(lines[1].len, 8);
  EXPECT_EQ(lines[2].len, 6);
}

TEST(EarLines, TheRestLiesBehindTheLinesFrontOnItsTop) {
  // Six depths 2 mm apart from -20 mm; heights 6.5, 7, 10, 10, 9.5, 7.5 (smoothed: 7, 7, 10, 10, 9.5, 9.5).
  const std::vector<double> depths = {-20, -18, -16, -14, -12, -10};
  const std::vector<EarCrease> creases = {at(5, 6.5), at(6, 7),   at(7, 10),
                                          at(8, 10),  at(9, 9.5), at(10, 7.5)};
  EarCreaseLine line = trace_crease_lines(creases, 5.0).at(0);
  ASSERT_EQ(line.len, 6);
  const EarSideFrame frame({{70, 0, 0}, {45, 0, 60}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, +1, 1.0});
  EarLineOptions o;
  const EarRootSide r = rest_of_line(line, creases, depths, o, frame, 3.0);
  ASSERT_TRUE(r.found);
  EXPECT_EQ(r.slices, 6);
  EXPECT_DOUBLE_EQ(r.back_mm, -20.0);
  EXPECT_DOUBLE_EQ(r.front_mm, -10.0);
  EXPECT_DOUBLE_EQ(r.depth_mm, -10.0 - o.rest_behind_front_mm);
  // The plateau (smoothed within 1.5 mm of 10): depths 2-5, at heights 10, 10, 9.5, 7.5.
  EXPECT_EQ(r.plateau, 4);
  EXPECT_DOUBLE_EQ(r.height_mm, (10 + 10 + 9.5 + 7.5) / 4.0);
  // The width: every depth weighted by its smoothed height above 10 - 4 mm (1, 1, 4, 4, 3.5, 3.5).
  EXPECT_NEAR(r.lateral_mm, (1 * 5 + 1 * 6 + 4 * 7 + 4 * 8 + 3.5 * 9 + 3.5 * 10) / 17.0, 1e-12);
  EXPECT_LT((r.point - frame.point(r.lateral_mm, r.depth_mm, r.height_mm)).norm(), 1e-12);
  ASSERT_EQ(r.ear_top.size(), 4u);
  ASSERT_EQ(r.ear_top[0].size(), 1u);  // these creases carry no top: the one point 3 mm out
  EXPECT_LT((r.ear_top[0][0] - frame.point(7 + 3.0, -16, 10)).norm(), 1e-12);
  // Without the weights, the plateau's mean width; a rest further back than the line's back end stops
  // there.
  o.depth_window_mm = 0.0, o.rest_behind_front_mm = 30.0;
  const EarRootSide p = rest_of_line(line, creases, depths, o, frame, 3.0);
  EXPECT_DOUBLE_EQ(p.lateral_mm, (7 + 8 + 9 + 10) / 4.0);
  EXPECT_DOUBLE_EQ(p.depth_mm, -20.0);
}

}  // namespace
}  // namespace lorgnette::fit
