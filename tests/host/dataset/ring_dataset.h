// A posed dataset for the loader's tests: `frames` grey RGB images f_0, f_1, ... of width x height
// (principal point in the middle, focal length `focal` px) on a ring of cameras 3 units from the
// origin, `step_rad` apart, written as transforms.json into `dir` (emptied first).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "host/dataset/dataset.h"

namespace lorgnette::testing {

inline std::filesystem::path write_ring_dataset(const std::filesystem::path& dir, int frames, int width,
                                                int height, float focal, double step_rad) {
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "images");
  std::vector<Camera> cams;
  std::vector<std::string> files;
  for (int i = 0; i < frames; ++i) {
    Camera c{};
    c.fx = c.fy = focal, c.cx = width / 2.0f, c.cy = height / 2.0f, c.width = width, c.height = height;
    const double a = step_rad * i;
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.topLeftCorner<3, 3>() << std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a);
    m.block<3, 1>(0, 3) << 3 * std::sin(a), 0.0, 3 * std::cos(a);
    dataset::set_camera_pose(c, m);
    cams.push_back(c);
    files.push_back("images/f_" + std::to_string(i) + ".png");
    write_image((dir / files.back()).string(), Image(width, height, 3, 0.5f));
  }
  dataset::write_transforms_json(dir.string(), cams, files);
  return dir;
}

}  // namespace lorgnette::testing
