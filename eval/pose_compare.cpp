// Similarity-aligned pose comparison (see pose_compare.h).
#include "eval/pose_compare.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "host/dataset/dataset.h"

namespace fs = std::filesystem;

namespace lorgnette::capture {
namespace {

// Reference poses by file stem, straight from the JSON (the reference images need not exist here).
std::map<std::string, Eigen::Matrix4d> read_reference(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error(fmt::format("cannot open reference '{}'", path));
  nlohmann::json j = nlohmann::json::parse(f);
  std::map<std::string, Eigen::Matrix4d> out;
  for (const auto& fr : j.at("frames")) {
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m(r, c) = fr.at("transform_matrix")[r][c].get<double>();
    out[fs::path(fr.at("file_path").get<std::string>()).stem().string()] = m;
  }
  return out;
}

}  // namespace

PoseAccuracy compare_poses(const std::string& dataset_dir, const std::string& reference) {
  dataset::LoadOptions lo;
  lo.load_images = false;
  dataset::Dataset ds = dataset::load_dataset(dataset_dir, lo);
  auto ref = read_reference(reference);
  std::vector<Eigen::Matrix4d> a, b;
  for (const auto& f : ds.frames) {
    auto it = ref.find(f.name);
    if (it == ref.end()) continue;
    a.push_back(dataset::camera_to_matrix(f.camera));
    b.push_back(it->second);
  }
  const int n = static_cast<int>(a.size());
  if (n < 3)
    throw std::runtime_error(fmt::format("only {} frames of '{}' appear in '{}'", n, dataset_dir, reference));
  Eigen::Matrix3Xd ours(3, n), theirs(3, n);
  for (int i = 0; i < n; ++i) ours.col(i) = a[i].block<3, 1>(0, 3), theirs.col(i) = b[i].block<3, 1>(0, 3);
  Eigen::Matrix4d sim = Eigen::umeyama(ours, theirs, true);
  PoseAccuracy acc;
  acc.matched = n;
  acc.scale = sim.block<3, 1>(0, 0).norm();
  Eigen::Matrix3d rot = sim.block<3, 3>(0, 0) / acc.scale;
  double spread = (theirs.colwise() - theirs.rowwise().mean()).colwise().norm().mean();
  for (int i = 0; i < n; ++i) {
    Eigen::AngleAxisd res(b[i].block<3, 3>(0, 0).transpose() * rot * a[i].block<3, 3>(0, 0));
    double deg = res.angle() * 180.0 / M_PI;
    for (int k = 0; k < 3; ++k) acc.residual_camera_deg[k] += deg * res.axis()[k] / n;
    Eigen::Vector3d c = sim.block<3, 3>(0, 0) * ours.col(i) + sim.block<3, 1>(0, 3);
    double rel = (c - theirs.col(i)).norm() / spread;
    acc.rotation_deg_mean += deg / n;
    acc.rotation_deg_max = std::max(acc.rotation_deg_max, deg);
    acc.centre_rel_mean += rel / n;
    acc.centre_rel_max = std::max(acc.centre_rel_max, rel);
  }
  return acc;
}

}  // namespace lorgnette::capture
