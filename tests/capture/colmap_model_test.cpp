// COLMAP model IO: a synthetic model with known poses round-trips exactly through the binary layout
// and through the text layout (17 significant digits), COLMAP's own text quirks (comments, empty
// POINTS2D lines, names with spaces) are read, and corrupt files give errors naming the file.
#include "capture/colmap_model.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "tests/capture/synthetic_model.h"

namespace fs = std::filesystem;
using namespace lorgnette::capture;

namespace {

using synthetic::tmp_dir;

// Exact comparison: both layouts must reproduce every double bit for bit.
void expect_same(const ColmapModel& a, const ColmapModel& b) {
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (const auto& [id, c] : a.cameras) {
    const auto& d = b.cameras.at(id);
    EXPECT_EQ(c.model, d.model);
    EXPECT_EQ(c.width, d.width);
    EXPECT_EQ(c.height, d.height);
    EXPECT_EQ(c.params, d.params);
  }
  ASSERT_EQ(a.images.size(), b.images.size());
  for (const auto& [id, im] : a.images) {
    const auto& jm = b.images.at(id);
    EXPECT_EQ(im.qvec, jm.qvec);
    EXPECT_EQ(im.tvec, jm.tvec);
    EXPECT_EQ(im.camera_id, jm.camera_id);
    EXPECT_EQ(im.name, jm.name);
    EXPECT_EQ(im.xys, jm.xys);
    EXPECT_EQ(im.point3d_ids, jm.point3d_ids);
  }
  ASSERT_EQ(a.points.size(), b.points.size());
  for (const auto& [id, p] : a.points) {
    const auto& q = b.points.at(id);
    EXPECT_EQ(p.xyz, q.xyz);
    EXPECT_EQ(p.rgb[0], q.rgb[0]);
    EXPECT_EQ(p.error, q.error);
    EXPECT_EQ(p.track, q.track);
  }
}

}  // namespace

TEST(ColmapModel, BinaryRoundTripIsExact) {
  auto scene = synthetic::make_synthetic_scene();
  fs::path dir = tmp_dir("model_bin");
  write_colmap_model(scene.model, dir, true);
  EXPECT_TRUE(fs::exists(dir / "images.bin"));
  expect_same(scene.model, read_colmap_model(dir));
}

TEST(ColmapModel, TextRoundTripIsExact) {
  auto scene = synthetic::make_synthetic_scene();
  fs::path dir = tmp_dir("model_txt");
  write_colmap_model(scene.model, dir, false);
  EXPECT_TRUE(fs::exists(dir / "points3D.txt"));
  expect_same(scene.model, read_colmap_model(dir));
}

TEST(ColmapModel, PosesSurviveTheQuaternionConversion) {
  // qvec/tvec written from known OpenGL c2w give the same c2w back (to rounding: 1e-12).
  auto scene = synthetic::make_synthetic_scene();
  for (const auto& [id, im] : scene.model.images) {
    Eigen::Matrix4d back = colmap_pose_to_opengl_c2w(im.qvec, im.tvec);
    EXPECT_LT((back - scene.c2w[id - 1]).cwiseAbs().maxCoeff(), 1e-12) << im.name;
    EXPECT_GE(im.qvec[0], 0.0);
  }
}

TEST(ColmapModel, ReadsColmapTextWithEmptyPointLinesAndSpacesInNames) {
  fs::path dir = tmp_dir("model_handwritten");
  std::ofstream(dir / "cameras.txt") << "# Camera list\n# Number of cameras: 1\n"
                                        "1 SIMPLE_RADIAL 640 480 500 320 240 0.01\n";
  std::ofstream(dir / "images.txt") << "# Image list\n"
                                       "1 1 0 0 0 0.5 0 0 1 my photo 1.jpg\n"
                                       "\n"
                                       "2 0.7071067811865476 0 0.7071067811865476 0 0 0 1 1 b.jpg\n"
                                       "10.5 20.25 7 30 40 -1\n";
  std::ofstream(dir / "points3D.txt") << "# points\n7 1 2 3 255 128 0 0.5 2 0\n";
  ColmapModel m = read_colmap_model(dir);
  ASSERT_EQ(m.images.size(), 2u);
  EXPECT_EQ(m.images.at(1).name, "my photo 1.jpg");
  EXPECT_TRUE(m.images.at(1).xys.empty());
  ASSERT_EQ(m.images.at(2).xys.size(), 2u);
  EXPECT_EQ(m.images.at(2).point3d_ids[1], -1);
  EXPECT_EQ(m.cameras.at(1).params.size(), 4u);
  EXPECT_EQ(m.points.at(7).rgb[1], 128);
  ASSERT_EQ(m.points.at(7).track.size(), 1u);
  EXPECT_EQ(m.points.at(7).track[0], std::make_pair(2u, 0u));
}

TEST(ColmapModel, CorruptFilesGiveClearErrors) {
  auto scene = synthetic::make_synthetic_scene(4, 10, 2);
  fs::path dir = tmp_dir("model_corrupt");
  write_colmap_model(scene.model, dir, true);
  fs::resize_file(dir / "images.bin", fs::file_size(dir / "images.bin") - 5);
  try {
    read_colmap_model(dir);
    FAIL() << "a truncated images.bin was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("images.bin"), std::string::npos) << e.what();
  }
  fs::path empty = tmp_dir("model_missing");
  EXPECT_THROW(read_colmap_model(empty), std::runtime_error);
  std::ofstream(empty / "cameras.txt") << "1 NOT_A_MODEL 1 1 1\n";
  std::ofstream(empty / "images.txt") << "";
  std::ofstream(empty / "points3D.txt") << "";
  EXPECT_THROW(read_colmap_model(empty), std::runtime_error);
}
