// Procrustes and the head frame on the mean face itself moved by a known similarity: exact recovery
// of the axes, the scale (mm per unit) and the PD; with noise, within stated tolerances.
#include "fit/head_frame.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "fit/landmark_ids.h"
#include "fit/mean_face.h"

namespace lorgnette::fit {
namespace {

const std::string kTeamMeanFace = std::string(LORGNETTE_DATA_DIR) + "/faces/mean-face-68.txt";

struct Moved {
  std::vector<Eigen::Vector3d> pts;
  Eigen::Matrix3d r;
  double s;
};

Moved move(const Face68& f, double noise_mm, unsigned seed) {
  Moved m;
  m.r = (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
  m.s = 1.0 / 57.0;  // Lee Perry-Smith-like: 57 mm per unit
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, noise_mm);
  for (const auto& p : f)
    m.pts.push_back(m.s * (m.r * (p + Eigen::Vector3d(n(rng), n(rng), n(rng)))) +
                    Eigen::Vector3d(0.1, 1.5, -0.3));
  return m;
}

TEST(MeanFace, LoadsInTheHeadFrame) {
  Face68 f = builtin_mean_face();
  ASSERT_EQ(f.size(), 68u);
  EXPECT_GT(f[lm::kEyeOuterL].x(), 40.0);  // wearer's left is +x
  EXPECT_GT(f[27].y(), f[33].y());         // bridge above the nose base: y up
  EXPECT_GT(f[lm::kNoseTip].z(), 30.0);    // nose tip forward: +z
  EXPECT_THROW(load_mean_face("/nonexistent/mean.txt"), std::runtime_error);
}

// The built-in table is the team's mean-face file, number for number (the file has 6 decimals).
TEST(MeanFace, BuiltInEqualsTheTeamFile) {
  if (!std::filesystem::exists(kTeamMeanFace)) GTEST_SKIP() << "team data not found: " << kTeamMeanFace;
  Face68 file = load_mean_face(kTeamMeanFace), built = builtin_mean_face();
  ASSERT_EQ(file.size(), built.size());
  for (size_t i = 0; i < file.size(); ++i) EXPECT_LT((file[i] - built[i]).norm(), 1e-9) << "landmark " << i;
}

// A file in the documented layout (all x, all y, all z; y down, z away) reads back to the same points,
// and an empty path means the built-in face; a file with too few numbers is refused by name.
TEST(MeanFace, FileRoundTripAndErrors) {
  const Face68& f = builtin_mean_face();
  std::string path = std::string(LORGNETTE_TEST_TMP) + "/mean-face-roundtrip.txt";
  {
    std::ofstream out(path);
    out.precision(17);
    for (int axis = 0; axis < 3; ++axis)
      for (const auto& p : f) out << (axis == 0 ? p.x() : -p[axis]) << "\n";
  }
  Face68 back = mean_face_or_builtin(path);
  for (size_t i = 0; i < f.size(); ++i) EXPECT_LT((back[i] - f[i]).norm(), 1e-12) << "landmark " << i;
  EXPECT_LT((mean_face_or_builtin("")[lm::kNoseTip] - f[lm::kNoseTip]).norm(), 1e-15);
  { std::ofstream(path) << "1 2 3\n"; }
  try {
    load_mean_face(path);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("found 3"), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
}

TEST(Procrustes, ExactSimilarity) {
  Face68 f = builtin_mean_face();
  Moved m = move(f, 0.0, 1);
  SimilarityFit s = procrustes(f, m.pts);
  EXPECT_NEAR(s.scale, m.s, 1e-12);
  EXPECT_LT((s.rotation - m.r).norm(), 1e-10);
  EXPECT_LT(s.rms, 1e-10);
}

TEST(Procrustes, CollinearThrows) {
  std::vector<Eigen::Vector3d> a{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  EXPECT_THROW(procrustes(a, a), std::runtime_error);
}

TEST(HeadFrame, AxesScaleAndPdExact) {
  Face68 f = builtin_mean_face();
  Moved m = move(f, 0.0, 1);
  HeadFrame h = estimate_head_frame(m.pts, std::vector<bool>(68, true), f);
  EXPECT_NEAR(h.mm_per_unit, 57.0, 1e-9);
  // d_fwd is the aligned mean face's forward exactly; the mean face's eye corners are not exactly
  // level (0.6 mm over 91 mm, 0.4 deg), so d_up follows them within 0.5 deg.
  EXPECT_LT((h.d_fwd - m.r.col(2)).norm(), 1e-10);
  Eigen::Vector3d eye = (m.pts[lm::kEyeOuterL] - m.pts[lm::kEyeOuterR]).normalized();
  EXPECT_GT(h.d_eye.dot(eye), std::cos(1.5 * M_PI / 180));  // the eye axis minus its 1.3 deg forward part
  EXPECT_GT(h.d_up.dot(m.r.col(1)), std::cos(0.5 * M_PI / 180));
  EXPECT_NEAR(h.d_eye.cross(h.d_up).dot(h.d_fwd), 1.0, 1e-12);  // right-handed
  Eigen::Vector3d cl = Eigen::Vector3d::Zero(), cr = Eigen::Vector3d::Zero();
  for (int i = 0; i < 6; ++i) cl += f[42 + i] / 6, cr += f[36 + i] / 6;
  EXPECT_NEAR(h.pd_mm, (cl - cr).norm(), 1e-9);
  EXPECT_NEAR((cl - cr).norm(), 62.0, 4.0);  // an average adult's PD
}

TEST(HeadFrame, NoisyLandmarks) {
  Face68 f = builtin_mean_face();
  Moved m = move(f, 1.0, 5);  // 1 mm landmark noise
  HeadFrame h = estimate_head_frame(m.pts, std::vector<bool>(68, true), f);
  // 31 points with 1 mm noise over a ~90 mm face: scale within 2 %, forward within 2 deg.
  EXPECT_NEAR(h.mm_per_unit, 57.0, 0.02 * 57.0);
  EXPECT_GT(h.d_fwd.dot(m.r.col(2)), std::cos(2.0 * M_PI / 180));
}

TEST(HeadFrame, TooFewLandmarksExplains) {
  Face68 f = builtin_mean_face();
  std::vector<bool> valid(68, false);
  valid[36] = valid[45] = true;
  try {
    estimate_head_frame(f, valid, f);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("triangulated"), std::string::npos);
  }
}

}  // namespace
}  // namespace lorgnette::fit
