// `capture` writes the landmark head box: a COLMAP model made from a rendered procedural-head dataset
// (exact poses, sparse points on the head and a far "room") goes through run_capture; the report
// says the box came from landmarks, and the transforms.json "aabb" contains the head (mapped through
// the written colmap_to_scene) while excluding the room that the sparse points span. Without the
// head box (or without faces) the sparse-point box is written and the report says so.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "capture/capture.h"
#include "face_dataset.h"
#include "host/dataset/dataset.h"
#include "synthetic_model.h"

namespace lorgnette::capture {
namespace {

namespace fs = std::filesystem;

// The head mesh vertices down to the neck margin, in the dataset (= COLMAP world) frame.
std::vector<Eigen::Vector3d> head_points() {
  const synth::Subject& s = synth::test::default_head();
  const double cut = -s.params.at("face_length").get<double>() - fit::HeadExtents{}.neck_mm;
  std::vector<Eigen::Vector3d> out;
  for (const auto& v : s.mesh.positions)
    if (v.y() >= cut) out.push_back(synth::transform_point(s.mesh_to_dataset, v).cast<double>());
  return out;
}

// A COLMAP model of the rendered dataset: its cameras, and sparse points on the head (every 400th
// vertex) and in a room 4 units around it, each seen by all images.
fs::path make_model_input(const std::string& name) {
  dataset::Dataset ds = dataset::load_dataset(test::face_dataset_dir());
  fs::path in = synthetic::tmp_dir(name);
  fs::create_directories(in / "images");
  ColmapModel m;
  const Camera& c0 = ds.frames[0].camera;
  m.cameras[1] = {1, "PINHOLE", c0.width, c0.height, {c0.fx, c0.fy, c0.cx, c0.cy}};
  for (size_t i = 0; i < ds.frames.size(); ++i) {
    ColmapImage im;
    im.id = uint32_t(i + 1);
    im.camera_id = 1;
    im.name = fs::path(ds.frames[i].image_path).filename().string();
    opengl_c2w_to_colmap_pose(dataset::camera_to_matrix(ds.frames[i].camera), im.qvec, im.tvec);
    fs::create_symlink(ds.frames[i].image_path, in / "images" / im.name);
    m.images[im.id] = im;
  }
  std::vector<Eigen::Vector3d> pts;
  auto head = head_points();
  for (size_t k = 0; k < head.size(); k += 400) pts.push_back(head[k]);
  for (int k = 0; k < 40; ++k)
    pts.push_back(Eigen::Vector3d(4.0 * std::cos(0.7 * k), 0.5 * std::sin(1.3 * k), -4.0 + 0.1 * k));
  for (size_t k = 0; k < pts.size(); ++k) {
    ColmapPoint3D p;
    p.id = k + 1;
    p.xyz = pts[k];
    p.error = 0.3;
    for (auto& [id, im] : m.images) {
      p.track.emplace_back(id, uint32_t(im.xys.size()));
      im.xys.emplace_back(1.0, 1.0);
      im.point3d_ids.push_back(int64_t(p.id));
    }
    m.points[p.id] = p;
  }
  fs::create_directories(in / "sparse" / "0");
  write_colmap_model(m, in / "sparse" / "0", false);
  return in;
}

TEST(CaptureHeadBox, WritesTheLandmarkHeadBox) {
  fs::path in = make_model_input("head_box_in");
  CaptureOptions opt;
  opt.input = in.string();
  opt.output = synthetic::tmp_dir("head_box_out").string();
  CaptureReport r = run_capture(opt);
  EXPECT_EQ(r.aabb_from, "landmarks") << r.to_json().dump(2);
  std::ifstream f(fs::path(opt.output) / "transforms.json");
  nlohmann::json t = nlohmann::json::parse(f);
  Eigen::Matrix4d to_scene;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) to_scene(i, j) = t["colmap_to_scene"][i][j];
  Eigen::Vector3d lo, hi;
  for (int a = 0; a < 3; ++a) lo[a] = t["aabb"][0][a], hi[a] = t["aabb"][1][a];
  EXPECT_NEAR(lo[0], r.aabb_min[0], 1e-9);
  // Contains the head (as in fit's head box test: neck below chin - 40 mm may be cut) ...
  for (const auto& p : head_points()) {
    Eigen::Vector3d q = (to_scene * p.homogeneous()).head<3>();
    ASSERT_TRUE((q.array() >= lo.array()).all() && (q.array() <= hi.array()).all())
        << q.transpose() << " outside " << lo.transpose() << " .. " << hi.transpose();
  }
  // ... and the room (4 units = 800 mm from the head) stays outside.
  Eigen::Vector3d room = (to_scene * Eigen::Vector3d(4.0, 0.0, -4.0).homogeneous()).head<3>();
  EXPECT_FALSE((room.array() >= lo.array()).all() && (room.array() <= hi.array()).all());
}

TEST(CaptureHeadBox, WithoutTheHeadBoxTheSparsePointsAreBoxed) {
  fs::path in = make_model_input("no_head_box_in");
  CaptureOptions opt;
  opt.input = in.string();
  opt.output = synthetic::tmp_dir("no_head_box_out").string();
  opt.head_box = false;
  CaptureReport r = run_capture(opt);
  EXPECT_EQ(r.aabb_from, "sparse points");
  EXPECT_NE(r.aabb_note.find("disabled"), std::string::npos) << r.aabb_note;
}

}  // namespace
}  // namespace lorgnette::capture
