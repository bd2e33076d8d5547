// NeRF adapter of the fit (see nerf_view_source.h).
#include "fit/nerf_view_source.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "host/util/file_kind.h"
#include "host/util/interrupt.h"
#include "kernels/train/occupancy.h"

namespace lorgnette::fit {

NerfViewSource::NerfViewSource(nerf::NerfModel& model, ViewPrior prior, render::RenderOptions options)
    : model_(model), prior_(std::move(prior)), options_(options), renderer_(model.runtime()) {
  options_.alpha = false;
  options_.background = {1.0f, 1.0f, 1.0f};
}

Image NerfViewSource::render(const Camera& cam) {
  // A fit renders dozens of views and has nothing to save: a stop request (Ctrl-C, SIGTERM) ends it
  // at the next view instead of after minutes.
  if (interrupted()) throw std::runtime_error("interrupted: the fit stopped and wrote nothing");
  render::RenderResult r = renderer_.render(model_, cam, nullptr, options_);
  Image out(r.rgba.width, r.rgba.height, 3);
  for (size_t i = 0; i < size_t(out.width) * out.height; ++i)
    for (int c = 0; c < 3; ++c) out.pixels[i * 3 + c] = r.rgba.pixels[i * r.rgba.channels + c];
  return out;
}

std::vector<bool> NerfViewSource::upload_positions(const std::vector<Eigen::Vector3f>& points, size_t start,
                                                   uint32_t n) {
  field::Field& f = model_.field();
  cl::Runtime& rt = model_.runtime();
  const uint32_t batch = f.max_batch();
  if (pos_.size() != 3u * batch)
    pos_ = cl::Buffer<float>(rt, 3u * batch), sigma_ = cl::Buffer<float>(rt, batch);
  const nerf::Aabb& box = model_.aabb();
  const nerf::OccupancyGrid& occ = model_.occupancy();
  std::vector<float> soa(3u * batch);
  std::vector<bool> inside(n);
  for (uint32_t i = 0; i < n; ++i) {
    const Eigen::Vector3f& p = points[start + i];
    float q[3];
    for (int a = 0; a < 3; ++a) {
      q[a] = (p[a] - box.min[a]) / box.extent(a);
      soa[a * batch + i] = std::clamp(q[a], 0.0f, 1.0f);
    }
    inside[i] = occ_test(occ.bits.data(), occ.res, q[0], q[1], q[2]) != 0;
  }
  pos_.write(rt, soa);
  return inside;
}

std::vector<float> NerfViewSource::density(const std::vector<Eigen::Vector3f>& points) {
  field::Field& f = model_.field();
  cl::Runtime& rt = model_.runtime();
  const uint32_t batch = f.max_batch();
  std::vector<float> out(points.size(), 0.0f);
  for (size_t start = 0; start < points.size(); start += batch) {
    const uint32_t n = uint32_t(std::min<size_t>(batch, points.size() - start));
    std::vector<bool> inside = upload_positions(points, start, n);
    f.density(pos_, n, sigma_);
    std::vector<float> s = sigma_.read(rt, n);
    for (uint32_t i = 0; i < n; ++i) out[start + i] = inside[i] ? s[i] : 0.0f;
  }
  return out;
}

std::vector<Eigen::Vector3f> NerfViewSource::colour(const std::vector<Eigen::Vector3f>& points,
                                                    const std::vector<Eigen::Vector3f>& dirs) {
  if (dirs.size() != points.size())
    throw std::invalid_argument("NerfViewSource::colour: one direction per point is needed");
  field::Field& f = model_.field();
  cl::Runtime& rt = model_.runtime();
  const uint32_t batch = f.max_batch();
  if (dir_.size() != 3u * batch)
    dir_ = cl::Buffer<float>(rt, 3u * batch), rgb_ = cl::Buffer<float>(rt, 3u * batch);
  std::vector<Eigen::Vector3f> out(points.size(), Eigen::Vector3f::Zero());
  std::vector<float> soa(3u * batch);
  for (size_t start = 0; start < points.size(); start += batch) {
    const uint32_t n = uint32_t(std::min<size_t>(batch, points.size() - start));
    upload_positions(points, start, n);
    for (uint32_t i = 0; i < n; ++i)
      for (int a = 0; a < 3; ++a) soa[a * batch + i] = dirs[start + i].normalized()[a];
    dir_.write(rt, soa);
    f.forward(pos_, dir_, n, sigma_, rgb_, false);
    std::vector<float> c = rgb_.read(rt, 3u * batch);
    for (uint32_t i = 0; i < n; ++i) out[start + i] = {c[i], c[batch + i], c[2 * batch + i]};
  }
  return out;
}

float NerfViewSource::surface_density() const { return kSurfaceOpticalDepth / model_.step(); }

Bounds NerfViewSource::bounds() const {
  Bounds b;
  for (int a = 0; a < 3; ++a) b.min[a] = model_.aabb().min[a], b.max[a] = model_.aabb().max[a];
  return b;
}

ViewPrior prior_from_transforms(const std::string& path, const nerf::NerfModel& model) {
  ViewPrior prior;
  // A path the model names may be anything by now: only a regular file is opened (a FIFO would
  // block the fit forever); anything else fits without the prior, as a missing file does.
  if (!is_regular_file_path(path)) {
    std::error_code ec;
    if (std::filesystem::exists(path, ec))
      spdlog::warn("fit: '{}' is not a regular file; fitting without the capture's cameras", path);
    return prior;
  }
  std::ifstream in(path);
  if (!in) return prior;
  nlohmann::json j;
  try {
    in >> j;
  } catch (const std::exception& e) {
    spdlog::warn("fit: cannot read the capture cameras from '{}': {}", path, e.what());
    return prior;
  }
  if (!j.contains("frames") || j["frames"].empty()) return prior;
  Eigen::Vector3d up = Eigen::Vector3d::Zero(), pos = Eigen::Vector3d::Zero();
  for (const auto& f : j["frames"]) {
    const auto& m = f.at("transform_matrix");
    up += Eigen::Vector3d(m[0][1].get<double>(), m[1][1].get<double>(), m[2][1].get<double>());
    pos += Eigen::Vector3d(m[0][3].get<double>(), m[1][3].get<double>(), m[2][3].get<double>());
  }
  pos /= double(j["frames"].size());
  const auto& n = model.normalisation;
  pos = pos * n.scale + Eigen::Vector3d(n.offset[0], n.offset[1], n.offset[2]);
  auto c = model.aabb().center();
  Eigen::Vector3d centre(c[0], c[1], c[2]);
  if (up.norm() > 1e-9) prior.up = up.normalized();
  if ((pos - centre).norm() > 1e-9) prior.front = (pos - centre).normalized();
  return prior;
}

}  // namespace lorgnette::fit
