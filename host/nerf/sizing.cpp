// Model sizing from the training views: look-at point, visual-hull carving from alpha masks,
// pixel-footprint resolution and surface-area table size (see sizing.h for the rules).
#include "host/nerf/sizing.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "host/nerf/occupancy_cells.h"
#include "kernels/train/occupancy.h"

namespace lorgnette::nerf {
namespace {

constexpr int kCarveRes = 64;
constexpr int kCarveViews = 48;

Eigen::Vector3d cam_origin(const Camera& c) { return {c.c2w[3], c.c2w[7], c.c2w[11]}; }
Eigen::Vector3d cam_forward(const Camera& c) {
  return -Eigen::Vector3d(c.c2w[2], c.c2w[6], c.c2w[10]).normalized();
}

bool has_alpha(const std::vector<View>& views) {
  return std::any_of(views.begin(), views.end(),
                     [](const View& v) { return v.image && v.image->has_transparency(); });
}

struct Carve {
  std::array<double, 3> min;
  double voxel;
  std::vector<uint8_t> kept;  // kCarveRes^3, x fastest
  bool at(int x, int y, int z) const {
    if (x < 0 || y < 0 || z < 0 || x >= kCarveRes || y >= kCarveRes || z >= kCarveRes) return false;
    return kept[(size_t(z) * kCarveRes + y) * kCarveRes + x];
  }
};

// Mask of one view dilated by the projected size of a carving voxel.
cv::Mat dilated_mask(const View& v, double voxel, double distance) {
  const Image& im = *v.image;
  cv::Mat mask(im.height, im.width, CV_8U);
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) mask.at<uint8_t>(y, x) = im.at(x, y, 3) > 0.02f ? 255 : 0;
  int r = std::min(32, int(std::ceil(v.camera.fx * voxel * 0.87 / std::max(distance, 1e-6))) + 1);
  cv::dilate(mask, mask, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1)));
  return mask;
}

Carve carve_visual_hull(const std::vector<View>& views, const Eigen::Vector3d& center, double half) {
  Carve c;
  c.voxel = 2.0 * half / kCarveRes;
  for (int a = 0; a < 3; ++a) c.min[a] = center[a] - half;
  c.kept.assign(size_t(kCarveRes) * kCarveRes * kCarveRes, 1);
  std::vector<uint16_t> seen(c.kept.size(), 0);
  size_t n_use = std::min<size_t>(views.size(), kCarveViews);
  for (size_t k = 0; k < n_use; ++k) {
    const View& v = views[k * views.size() / n_use];
    // Dilation for a voxel at the look-at distance; nearer voxels project larger, which the
    // one-voxel dilation of the hull below absorbs for the object (nearer voxels are mostly empty).
    cv::Mat mask = dilated_mask(v, c.voxel, (cam_origin(v.camera) - center).norm());
    for (int z = 0; z < kCarveRes; ++z)
      for (int y = 0; y < kCarveRes; ++y)
        for (int x = 0; x < kCarveRes; ++x) {
          size_t i = (size_t(z) * kCarveRes + y) * kCarveRes + x;
          if (!c.kept[i]) continue;
          LgnVec3 p = lgn_vec3(float(c.min[0] + (x + 0.5) * c.voxel), float(c.min[1] + (y + 0.5) * c.voxel),
                               float(c.min[2] + (z + 0.5) * c.voxel));
          float u, w;
          if (camera_project(&v.camera, p, &u, &w) <= 0.0f) continue;
          if (!(u >= 0 && w >= 0 && u < v.camera.width && w < v.camera.height)) continue;
          ++seen[i];
          if (!mask.at<uint8_t>(int(w), int(u))) c.kept[i] = 0;
        }
  }
  // Only cells seen by half of the views count as constrained: a cell right in front of a few
  // cameras projects onto the object in those views and is outside the others' frustums (the
  // object itself is in the frustum of every view in a capture centred on it).
  const size_t min_seen = std::max<size_t>(2, n_use / 2);
  for (size_t i = 0; i < c.kept.size(); ++i) c.kept[i] = c.kept[i] && seen[i] >= min_seen;
  // Dilate by one voxel: conservative against thin structures between voxel centres.
  Carve d = c;
  for (int z = 0; z < kCarveRes; ++z)
    for (int y = 0; y < kCarveRes; ++y)
      for (int x = 0; x < kCarveRes; ++x)
        for (int dz = -1; dz <= 1; ++dz)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
              if (c.at(x + dx, y + dy, z + dz)) d.kept[(size_t(z) * kCarveRes + y) * kCarveRes + x] = 1;
  return d;
}

// Bounds of the kept voxels; the boundary area in scene units^2.
bool hull_bounds(const Carve& c, Aabb* box, double* area) {
  int lo[3] = {kCarveRes, kCarveRes, kCarveRes}, hi[3] = {-1, -1, -1};
  uint64_t boundary = 0;
  for (int z = 0; z < kCarveRes; ++z)
    for (int y = 0; y < kCarveRes; ++y)
      for (int x = 0; x < kCarveRes; ++x) {
        if (!c.at(x, y, z)) continue;
        int p[3] = {x, y, z};
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
        boundary += !c.at(x - 1, y, z) + !c.at(x + 1, y, z) + !c.at(x, y - 1, z) + !c.at(x, y + 1, z) +
                    !c.at(x, y, z - 1) + !c.at(x, y, z + 1);
      }
  if (hi[0] < 0) return false;
  for (int a = 0; a < 3; ++a) {
    box->min[a] = float(c.min[a] + lo[a] * c.voxel);
    box->max[a] = float(c.min[a] + (hi[a] + 1) * c.voxel);
  }
  *area = double(boundary) * c.voxel * c.voxel;
  return true;
}

// Occupancy mask at resolution res over `box`: a cell is allowed when any of its corners or its
// centre lies in a kept carving voxel.
std::vector<uint32_t> mask_from_hull(const Carve& c, const Aabb& box, uint32_t res) {
  return occupancy_mask_where<double>(box, res, [&](const double* p) {
    int v[3];
    for (int a = 0; a < 3; ++a) v[a] = int(std::floor((p[a] - c.min[a]) / c.voxel));
    return c.at(v[0], v[1], v[2]);
  });
}

// Nearest distance from any camera to a kept hull cell (the closest the object gets to a camera).
double nearest_hull_distance(const std::vector<View>& views, const Carve& c) {
  double best = 1e30;
  for (int z = 0; z < kCarveRes; ++z)
    for (int y = 0; y < kCarveRes; ++y)
      for (int x = 0; x < kCarveRes; ++x) {
        if (!c.at(x, y, z)) continue;
        Eigen::Vector3d p(c.min[0] + (x + 0.5) * c.voxel, c.min[1] + (y + 0.5) * c.voxel,
                          c.min[2] + (z + 0.5) * c.voxel);
        for (const auto& v : views) best = std::min(best, (cam_origin(v.camera) - p).norm());
      }
  return std::max(best - 0.87 * c.voxel, 0.5 * c.voxel);
}

double nearest_camera_distance(const std::vector<View>& views, const Aabb& box) {
  double best = 1e30;
  for (const auto& v : views) {
    Eigen::Vector3d o = cam_origin(v.camera), q;
    for (int a = 0; a < 3; ++a) q[a] = std::clamp(o[a], double(box.min[a]), double(box.max[a]));
    double to_center = (o - Eigen::Vector3d(box.center()[0], box.center()[1], box.center()[2])).norm();
    best = std::min(best, std::max((o - q).norm(), 0.05 * to_center));
  }
  return best;
}

}  // namespace

std::array<float, 3> cameras_look_at(const std::vector<Camera>& cameras) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero(), centroid = Eigen::Vector3d::Zero();
  for (const auto& c : cameras) {
    Eigen::Vector3d o = cam_origin(c), d = cam_forward(c);
    Eigen::Matrix3d M = Eigen::Matrix3d::Identity() - d * d.transpose();
    A += M;
    b += M * o;
    centroid += o / double(cameras.size());
  }
  Eigen::Vector3d p = centroid;
  // A is symmetric positive semi-definite: its eigenvalues (ascending) are its singular values.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(A, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d& ev = eig.eigenvalues();
  if (ev[0] > 1e-3 * ev[2]) p = A.ldlt().solve(b);
  return {float(p[0]), float(p[1]), float(p[2])};
}

uint32_t device_batch_log2(const cl::DeviceInfo& device) { return device.is_gpu ? 18u : 16u; }

ModelSizing choose_model_size(const std::vector<View>& views, const SizingOverrides& ov) {
  if (views.empty()) throw std::runtime_error("cannot size a model without training views");
  std::vector<Camera> cams;
  for (const auto& v : views) cams.push_back(v.camera);
  ModelSizing s;
  s.look_at = cameras_look_at(cams);
  Eigen::Vector3d center(s.look_at[0], s.look_at[1], s.look_at[2]);
  std::vector<double> dist;
  for (const auto& c : cams) dist.push_back((cam_origin(c) - center).norm());
  double nearest = std::max(*std::min_element(dist.begin(), dist.end()), 1e-6);
  std::nth_element(dist.begin(), dist.begin() + dist.size() / 2, dist.end());
  double median = std::max(dist[dist.size() / 2], 1e-6);
  s.occupancy_resolution = ov.occupancy_resolution.value_or(64);
  double area = 0.0;
  std::optional<Carve> hull;
  if (ov.aabb) {
    s.aabb = *ov.aabb;
    s.from = "override";
  } else if (ov.use_masks && has_alpha(views)) {
    hull = carve_visual_hull(views, center, 0.5 * nearest);
    if (hull_bounds(*hull, &s.aabb, &area)) {
      s.from = "alpha masks (visual hull)";
    } else {
      spdlog::warn("the alpha masks leave nothing visible in every view: falling back to a camera-based box");
      hull.reset();
    }
  }
  if (s.from.empty()) {
    double half = ov.aabb_scale * 0.5 * median;
    for (int a = 0; a < 3; ++a)
      s.aabb.min[a] = float(center[a] - half), s.aabb.max[a] = float(center[a] + half);
    s.from = fmt::format(
        "cameras (look-at point, half-size {:.3g} = aabb_scale {} x half the median camera distance)", half,
        ov.aabb_scale);
  }
  if (!s.aabb.valid()) throw std::runtime_error("the bounding box is empty or not finite: check --aabb");
  if (area <= 0.0)
    area = 2.0 * (s.aabb.extent(0) * s.aabb.extent(1) + s.aabb.extent(1) * s.aabb.extent(2) +
                  s.aabb.extent(0) * s.aabb.extent(2));
  if (hull) s.occupancy_mask = mask_from_hull(*hull, s.aabb, s.occupancy_resolution);
  float fx = 0.0f;
  for (const auto& c : cams) fx = std::max({fx, c.fx, c.fy});
  s.nearest_distance = hull ? nearest_hull_distance(views, *hull) : nearest_camera_distance(views, s.aabb);
  s.pixel_footprint = s.nearest_distance / fx;
  double finest = std::clamp(s.aabb.max_extent() / s.pixel_footprint, 32.0, 4096.0);
  s.field.finest_resolution = ov.finest_resolution.value_or(uint32_t(std::ceil(finest)));
  double cell = s.aabb.max_extent() / s.field.finest_resolution;
  double surface_cells = area / (cell * cell);
  uint32_t log2t = uint32_t(std::clamp(std::ceil(std::log2(std::max(surface_cells, 1.0))), 14.0, 19.0));
  s.field.log2_table_size = ov.log2_table_size.value_or(log2t);
  if (ov.levels) s.field.levels = *ov.levels;
  s.field.validate();
  s.step = ov.step.value_or(float(std::sqrt(3.0) * s.aabb.max_extent() / ov.steps_per_diagonal));
  return s;
}

std::string ModelSizing::summary() const {
  return fmt::format(
      "model: AABB [{:.3f} {:.3f} {:.3f}] .. [{:.3f} {:.3f} {:.3f}] from {}; nearest camera {:.3f} units, "
      "pixel "
      "footprint {:.2e} -> finest grid {} ({} levels from {}); hash table 2^{}; occupancy {}^3{}; step "
      "{:.4g}; "
      "{:.1f} MB of parameters",
      aabb.min[0], aabb.min[1], aabb.min[2], aabb.max[0], aabb.max[1], aabb.max[2], from, nearest_distance,
      pixel_footprint, field.finest_resolution, field.levels, field.base_resolution, field.log2_table_size,
      occupancy_resolution, occupancy_mask.empty() ? "" : " (visual-hull mask)", step, megabytes());
}

}  // namespace lorgnette::nerf
