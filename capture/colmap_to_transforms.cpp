// COLMAP model -> scene frame: poses flipped to OpenGL camera axes, world rotated so the mean camera
// up is +z (instant-ngp's colmap2nerf convention), centred and scaled on a robust box around the
// sparse points near where the optical axes meet (the subject), then written as transforms.json.
#include "capture/colmap_to_transforms.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "host/dataset/dataset.h"

namespace lorgnette::capture {
namespace {

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  double pos = q * (v.size() - 1);
  size_t i = static_cast<size_t>(std::floor(pos));
  size_t j = std::min(i + 1, v.size() - 1);
  return v[i] + (pos - i) * (v[j] - v[i]);
}

// Least-squares point closest to all optical axes (camera centre c, viewing direction d); falls back
// to the mean of the centres pushed along the mean direction when the axes are (nearly) parallel.
Eigen::Vector3d focus_point(const std::vector<Eigen::Matrix4d>& c2ws) {
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const auto& m : c2ws) {
    Eigen::Vector3d d = -m.block<3, 1>(0, 2).normalized();
    Eigen::Matrix3d p = Eigen::Matrix3d::Identity() - d * d.transpose();
    a += p;
    b += p * m.block<3, 1>(0, 3);
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(a);
  if (es.eigenvalues()[0] > 1e-3 * static_cast<double>(c2ws.size())) return a.ldlt().solve(b);
  return Eigen::Vector3d::Constant(std::nan(""));
}

struct SubjectBox {
  Eigen::Vector3d min, max;
  size_t points = 0;
};

// Robust box (in the up-aligned frame `rot`) of the sparse points near the focus point.
SubjectBox subject_box(const ColmapModel& model, const std::vector<Eigen::Matrix4d>& c2ws,
                       const Eigen::Matrix3d& rot, const ConvertOptions& opt) {
  std::vector<Eigen::Vector3d> pts;
  for (const auto& [id, p] : model.points)
    if (p.track.size() >= opt.min_track_length) pts.push_back(p.xyz);
  if (pts.size() < 20)  // too few well-tracked points: take every point
    for (const auto& [id, p] : model.points)
      if (p.track.size() < opt.min_track_length) pts.push_back(p.xyz);
  Eigen::Vector3d focus = focus_point(c2ws);
  if (!focus.allFinite()) {  // parallel axes: the median point stands in for the focus
    focus.setZero();
    for (int k = 0; k < 3 && !pts.empty(); ++k) {
      std::vector<double> v;
      for (const auto& p : pts) v.push_back(p[k]);
      focus[k] = quantile(v, 0.5);
    }
  }
  std::vector<double> cam_dist;
  for (const auto& m : c2ws) cam_dist.push_back((m.block<3, 1>(0, 3) - focus).norm());
  double radius = opt.subject_radius_fraction * quantile(cam_dist, 0.5);
  std::vector<Eigen::Vector3d> subject;
  for (const auto& p : pts)
    if ((p - focus).norm() < radius) subject.push_back(rot * p);
  SubjectBox box;
  box.points = subject.size();
  if (subject.size() < 8) {  // nothing reliable: a cube of the subject radius around the focus
    box.min = rot * focus - Eigen::Vector3d::Constant(0.5 * radius);
    box.max = rot * focus + Eigen::Vector3d::Constant(0.5 * radius);
    return box;
  }
  for (int k = 0; k < 3; ++k) {
    std::vector<double> v;
    for (const auto& p : subject) v.push_back(p[k]);
    double lo = quantile(v, opt.box_percentile), hi = quantile(v, 1.0 - opt.box_percentile);
    double pad = opt.box_padding * std::max(hi - lo, 1e-9);
    box.min[k] = lo - pad;
    box.max[k] = hi + pad;
  }
  return box;
}

}  // namespace

Eigen::Matrix4d colmap_pose_to_opengl_c2w(const Eigen::Vector4d& qvec, const Eigen::Vector3d& tvec) {
  Eigen::Matrix3d r = colmap_qvec_to_rotation(qvec);
  Eigen::Matrix4d c2w = Eigen::Matrix4d::Identity();
  c2w.block<3, 3>(0, 0) = r.transpose();
  c2w.block<3, 1>(0, 3) = -r.transpose() * tvec;
  // COLMAP cameras look down +z with y down; OpenGL cameras look down -z with y up.
  c2w.col(1) *= -1;
  c2w.col(2) *= -1;
  return c2w;
}

void opengl_c2w_to_colmap_pose(const Eigen::Matrix4d& c2w, Eigen::Vector4d& qvec, Eigen::Vector3d& tvec) {
  Eigen::Matrix3d r = c2w.block<3, 3>(0, 0);
  r.col(1) *= -1;
  r.col(2) *= -1;
  Eigen::Matrix3d w2c = r.transpose();
  qvec = colmap_rotation_to_qvec(w2c);
  tvec = -w2c * c2w.block<3, 1>(0, 3);
}

ConvertedScene convert_colmap_model(const ColmapModel& model, const ConvertOptions& opt) {
  if (model.images.empty()) throw std::runtime_error("the COLMAP model has no registered images");
  std::vector<const ColmapImage*> images;
  for (const auto& [id, im] : model.images) images.push_back(&im);
  std::sort(images.begin(), images.end(), [](auto* a, auto* b) { return a->name < b->name; });
  std::vector<Eigen::Matrix4d> c2ws;
  Eigen::Vector3d up = Eigen::Vector3d::Zero();
  for (const auto* im : images) {
    c2ws.push_back(colmap_pose_to_opengl_c2w(im->qvec, im->tvec));
    up += c2ws.back().block<3, 1>(0, 1);
  }
  Eigen::Matrix3d rot = Eigen::Matrix3d::Identity();
  if (up.norm() > 1e-9)  // opposite cameras can cancel out: then keep COLMAP's axes
    rot = Eigen::Quaterniond::FromTwoVectors(up.normalized(), Eigen::Vector3d::UnitZ()).toRotationMatrix();

  SubjectBox box = subject_box(model, c2ws, rot, opt);
  Eigen::Vector3d centre = 0.5 * (box.min + box.max);  // in the rotated frame
  double half = 0.5 * (box.max - box.min).maxCoeff();
  ConvertedScene scene;
  scene.scale = 1.0 / half;  // the box's longest side spans [-1, 1]
  scene.colmap_to_scene.block<3, 3>(0, 0) = scene.scale * rot;
  scene.colmap_to_scene.block<3, 1>(0, 3) = -scene.scale * centre;
  scene.aabb_min = scene.scale * (box.min - centre);
  scene.aabb_max = scene.scale * (box.max - centre);
  scene.subject_points = box.points;
  for (size_t i = 0; i < images.size(); ++i) {
    ConvertedFrame f;
    f.file_path = opt.image_prefix + images[i]->name;
    f.colmap_image_id = images[i]->id;
    f.colmap_camera_id = images[i]->camera_id;
    f.c2w.block<3, 3>(0, 0) = rot * c2ws[i].block<3, 3>(0, 0);
    f.c2w.block<3, 1>(0, 3) = scene.scale * (rot * c2ws[i].block<3, 1>(0, 3) - centre);
    scene.frames.push_back(f);
  }
  double err = 0;
  for (const auto& [id, p] : model.points) err += p.error;
  scene.mean_reprojection_error = model.points.empty() ? 0 : err / model.points.size();
  return scene;
}

Camera camera_from_colmap(const ColmapCamera& c) {
  Camera cam{};
  const auto& p = c.params;
  auto bad = [&] {
    return std::runtime_error(
        fmt::format("COLMAP camera {} uses the {} model, which has no OPENCV equivalent: re-run COLMAP with "
                    "--ImageReader.camera_model OPENCV",
                    c.id, c.model));
  };
  if (p.size() != colmap_camera_param_count(c.model)) throw bad();
  double fx = p[0], fy = p[0], cx = p[1], cy = p[2], k1 = 0, k2 = 0, p1 = 0, p2 = 0;
  if (c.model == "SIMPLE_PINHOLE") {
  } else if (c.model == "SIMPLE_RADIAL") {
    k1 = p[3];
  } else if (c.model == "RADIAL") {
    k1 = p[3], k2 = p[4];
  } else if (c.model == "PINHOLE" || c.model == "OPENCV" || c.model == "FULL_OPENCV") {
    fy = p[1], cx = p[2], cy = p[3];
    if (c.model != "PINHOLE") k1 = p[4], k2 = p[5], p1 = p[6], p2 = p[7];
    if (c.model == "FULL_OPENCV" && (p[8] != 0 || p[9] != 0 || p[10] != 0 || p[11] != 0)) throw bad();
  } else {
    throw bad();
  }
  cam.fx = float(fx), cam.fy = float(fy), cam.cx = float(cx), cam.cy = float(cy);
  cam.k1 = float(k1), cam.k2 = float(k2), cam.p1 = float(p1), cam.p2 = float(p2);
  cam.width = static_cast<lgn_uint>(c.width);
  cam.height = static_cast<lgn_uint>(c.height);
  return cam;
}

void write_capture_transforms(const std::string& dir, const ColmapModel& model, const ConvertedScene& scene) {
  std::vector<Camera> cameras;
  std::vector<std::string> files;
  for (const auto& f : scene.frames) {
    Camera cam = camera_from_colmap(model.cameras.at(f.colmap_camera_id));
    dataset::set_camera_pose(cam, f.c2w);
    cameras.push_back(cam);
    files.push_back(f.file_path);
  }
  nlohmann::json to_scene = nlohmann::json::array();
  for (int r = 0; r < 4; ++r)
    to_scene.push_back({scene.colmap_to_scene(r, 0), scene.colmap_to_scene(r, 1), scene.colmap_to_scene(r, 2),
                        scene.colmap_to_scene(r, 3)});
  nlohmann::json extra = {{"aabb",
                           {{scene.aabb_min.x(), scene.aabb_min.y(), scene.aabb_min.z()},
                            {scene.aabb_max.x(), scene.aabb_max.y(), scene.aabb_max.z()}}},
                          {"colmap_to_scene", to_scene},
                          {"scene_scale", scene.scale},
                          {"up", {0.0, 0.0, 1.0}},
                          {"mean_reprojection_error_px", scene.mean_reprojection_error},
                          {"generator", "lorgnette capture"}};
  dataset::write_transforms_json(dir, cameras, files, extra);
}

}  // namespace lorgnette::capture
