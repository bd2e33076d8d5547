// COLMAP model -> transforms.json: on a synthetic model with known poses (written by the test in
// binary and in text and read back), the scene poses are exactly the known poses mapped by the
// reported similarity (to 1e-9), the mean camera up becomes +z, the subject box holds the head and
// not the room, and host/dataset's loader reads the written file back with the same cameras.
#include "capture/colmap_to_transforms.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "host/dataset/dataset.h"
#include "tests/capture/synthetic_model.h"

namespace fs = std::filesystem;
using namespace lorgnette;
using namespace lorgnette::capture;

namespace {

using synthetic::tmp_dir;

Eigen::Vector3d to_scene(const ConvertedScene& s, const Eigen::Vector3d& p) {
  return s.colmap_to_scene.block<3, 3>(0, 0) * p + s.colmap_to_scene.block<3, 1>(0, 3);
}

void check_conversion(const synthetic::SyntheticScene& syn, const ColmapModel& model) {
  ConvertedScene s = convert_colmap_model(model);
  ASSERT_EQ(s.frames.size(), syn.c2w.size());
  Eigen::Matrix3d rot = s.colmap_to_scene.block<3, 3>(0, 0) / s.scale;
  EXPECT_LT((rot * rot.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(rot.determinant(), 1.0, 1e-12);
  Eigen::Vector3d up = Eigen::Vector3d::Zero();
  for (const auto& f : s.frames) {
    const Eigen::Matrix4d& known = syn.c2w[f.colmap_image_id - 1];
    // Rounding only: double arithmetic on values of order 1 (1e-9 leaves a wide margin).
    EXPECT_LT((f.c2w.block<3, 3>(0, 0) - rot * known.block<3, 3>(0, 0)).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LT((f.c2w.block<3, 1>(0, 3) - to_scene(s, known.block<3, 1>(0, 3))).norm(), 1e-9);
    up += f.c2w.block<3, 1>(0, 1);
  }
  EXPECT_LT((up.normalized() - Eigen::Vector3d::UnitZ()).norm(), 1e-9);
  // Head points (a sphere) inside the padded box, room points outside it.
  size_t head_in = 0, room_in = 0;
  auto inside = [&](const Eigen::Vector3d& p) {
    return (p.array() >= s.aabb_min.array()).all() && (p.array() <= s.aabb_max.array()).all();
  };
  for (auto id : syn.head_ids) head_in += inside(to_scene(s, model.points.at(id).xyz));
  for (auto id : syn.room_ids) room_in += inside(to_scene(s, model.points.at(id).xyz));
  EXPECT_EQ(head_in, syn.head_ids.size());
  EXPECT_EQ(room_in, 0u);
  // Centred and scaled on the head: centre near the origin, longest side spans [-1, 1].
  EXPECT_LT(to_scene(s, syn.head_centre).norm(), 0.1);
  EXPECT_NEAR((s.aabb_max - s.aabb_min).maxCoeff(), 2.0, 1e-12);
  EXPECT_EQ(s.subject_points, syn.head_ids.size());
}

}  // namespace

TEST(ColmapToTransforms, BinaryModelGivesTheKnownPoses) {
  auto syn = synthetic::make_synthetic_scene();
  fs::path dir = tmp_dir("convert_bin");
  write_colmap_model(syn.model, dir, true);
  check_conversion(syn, read_colmap_model(dir));
}

TEST(ColmapToTransforms, TextModelGivesTheKnownPoses) {
  auto syn = synthetic::make_synthetic_scene();
  fs::path dir = tmp_dir("convert_txt");
  write_colmap_model(syn.model, dir, false);
  check_conversion(syn, read_colmap_model(dir));
}

TEST(ColmapToTransforms, CameraModelsMapToOpencv) {
  ColmapCamera c{1, "SIMPLE_RADIAL", 640, 480, {500, 320, 240, 0.02}};
  Camera cam = camera_from_colmap(c);
  EXPECT_FLOAT_EQ(cam.fx, 500.0f);
  EXPECT_FLOAT_EQ(cam.fy, 500.0f);
  EXPECT_FLOAT_EQ(cam.cy, 240.0f);
  EXPECT_FLOAT_EQ(cam.k1, 0.02f);
  EXPECT_EQ(cam.width, 640u);
  ColmapCamera fisheye{2, "OPENCV_FISHEYE", 640, 480, {1, 1, 1, 1, 0, 0, 0, 0}};
  EXPECT_THROW(camera_from_colmap(fisheye), std::runtime_error);
}

TEST(ColmapToTransforms, WrittenFileLoadsWithTheSameCameras) {
  auto syn = synthetic::make_synthetic_scene();
  fs::path dir = tmp_dir("convert_write");
  fs::create_directories(dir / "images");
  for (const auto& [id, im] : syn.model.images)
    cv::imwrite((dir / "images" / im.name).string(), cv::Mat(48, 64, CV_8UC3, cv::Scalar(90, 120, 150)));
  ConvertedScene s = convert_colmap_model(syn.model);
  write_capture_transforms(dir.string(), syn.model, s);
  dataset::LoadOptions lo;
  lo.load_images = false;
  dataset::Dataset ds = dataset::load_dataset(dir.string(), lo);
  ASSERT_EQ(ds.frames.size(), s.frames.size());
  const auto& p = syn.model.cameras.at(1).params;
  for (const auto& f : ds.frames) {
    // Camera stores floats: about 1e-7 relative, so 1e-4 px and 1e-5 on pose entries of order 1.
    EXPECT_NEAR(f.camera.fx, p[0], 1e-4);
    EXPECT_NEAR(f.camera.cy, p[3], 1e-4);
    EXPECT_NEAR(f.camera.k2, p[5], 1e-7);
    EXPECT_EQ(f.camera.width, 64u);
    const ConvertedFrame* match = nullptr;
    for (const auto& g : s.frames)
      if (fs::path(g.file_path).stem().string() == f.name) match = &g;
    ASSERT_NE(match, nullptr) << f.name;
    EXPECT_LT((dataset::camera_to_matrix(f.camera) - match->c2w).cwiseAbs().maxCoeff(), 1e-5) << f.name;
  }
}
