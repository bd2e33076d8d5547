// A synthetic COLMAP model with known poses for the capture tests: cameras on a tilted ring around
// a "head" (a sphere of points seen by every camera) in a room (far points seen by two cameras).
#pragma once
#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "capture/colmap_model.h"
#include "capture/colmap_to_transforms.h"

namespace lorgnette::capture::synthetic {

// A fresh, empty directory for one test under the build's test-tmp/capture.
inline std::filesystem::path tmp_dir(const std::string& name) {
  std::filesystem::path p = std::filesystem::path(LORGNETTE_TEST_TMP) / "capture" / name;
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p;
}

struct SyntheticScene {
  ColmapModel model;
  std::vector<Eigen::Matrix4d> c2w;  // OpenGL c2w per image id - 1, in COLMAP's world
  Eigen::Vector3d head_centre{0.3, -0.2, 2.0};
  double head_radius = 0.12;
  Eigen::Vector3d world_up;  // the ring's up direction (unit)
  std::vector<uint64_t> head_ids, room_ids;
};

// Camera looking from `eye` at `target` with up `up`, OpenGL axes.
inline Eigen::Matrix4d look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                               const Eigen::Vector3d& up) {
  Eigen::Vector3d back = (eye - target).normalized();
  Eigen::Vector3d right = up.cross(back).normalized();
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<3, 1>(0, 0) = right;
  m.block<3, 1>(0, 1) = back.cross(right);
  m.block<3, 1>(0, 2) = back;
  m.block<3, 1>(0, 3) = eye;
  return m;
}

// arc_rad: the cameras spread over [-arc_rad, arc_rad] about the head (1.2: about 140 degrees).
inline SyntheticScene make_synthetic_scene(int cameras = 9, int head_points = 300, int room_points = 60,
                                           double arc_rad = 1.2) {
  SyntheticScene s;
  std::mt19937 rng(1234);
  std::normal_distribution<double> g(0.0, 1.0);
  s.world_up = Eigen::Vector3d(0.2, -1.0, 0.1).normalized();  // COLMAP worlds are arbitrary
  Eigen::Vector3d a = s.world_up.unitOrthogonal(), b = s.world_up.cross(a);
  ColmapCamera cam;
  cam.id = 1;
  cam.model = "OPENCV";
  cam.width = 64;
  cam.height = 48;
  cam.params = {60.5, 61.25, 32.1, 23.9, 0.012, -0.0034, 0.0005, -0.0002};
  s.model.cameras[1] = cam;
  for (int i = 0; i < cameras; ++i) {
    double ang = -arc_rad + 2 * arc_rad * i / (cameras - 1);
    Eigen::Vector3d eye = s.head_centre + 0.6 * (std::cos(ang) * a + std::sin(ang) * b) + 0.05 * s.world_up;
    s.c2w.push_back(look_at(eye, s.head_centre, s.world_up));
    ColmapImage im;
    im.id = static_cast<uint32_t>(i + 1);
    im.camera_id = 1;
    im.name = "frame_" + std::to_string(1000 + i) + ".jpg";
    opengl_c2w_to_colmap_pose(s.c2w.back(), im.qvec, im.tvec);
    s.model.images[im.id] = im;
  }
  uint64_t id = 1;
  for (int k = 0; k < head_points + room_points; ++k, ++id) {
    ColmapPoint3D p;
    p.id = id;
    Eigen::Vector3d d(g(rng), g(rng), g(rng));
    bool head = k < head_points;
    p.xyz = head ? Eigen::Vector3d(s.head_centre + s.head_radius * d.normalized())
                 : Eigen::Vector3d(s.head_centre + 3.0 * d.normalized());
    p.rgb[0] = static_cast<uint8_t>(k % 256);
    p.error = 0.25 + 0.001 * k;
    int seen = head ? cameras : 2;
    for (int c = 0; c < seen; ++c) {
      uint32_t image_id = static_cast<uint32_t>(1 + (k + c) % cameras);
      auto& im = s.model.images[image_id];
      p.track.emplace_back(image_id, static_cast<uint32_t>(im.xys.size()));
      im.xys.emplace_back(0.5 + k % 64, 0.25 + (k * 7) % 48);
      im.point3d_ids.push_back(static_cast<int64_t>(id));
    }
    (head ? s.head_ids : s.room_ids).push_back(id);
    s.model.points[id] = p;
  }
  // An observation without a 3D point, as COLMAP keeps them.
  s.model.images[1].xys.emplace_back(3.5, 4.5);
  s.model.images[1].point3d_ids.push_back(-1);
  return s;
}

}  // namespace lorgnette::capture::synthetic
