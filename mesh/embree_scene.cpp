// Embree 3 device/scene RAII and hit reconstruction; see embree_scene.h.
#include "mesh/embree_scene.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <Eigen/Geometry>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace lorgnette::mesh {
namespace {

void error_callback(void* /*user*/, RTCError code, const char* message) {
  spdlog::error("Embree error {}: {}", static_cast<int>(code), message ? message : "");
}

void check_device(RTCDevice device, const char* what) {
  RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE)
    throw std::runtime_error(
        fmt::format("Embree failed while {} (error code {}); see the log above", what, static_cast<int>(e)));
}

// One ray for rtcIntersect1 (inside an RTCRayHit) and rtcOccluded1 alike: every ray, no motion blur.
RTCRay make_ray(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float tnear, float tfar) {
  RTCRay ray;
  ray.org_x = origin.x(), ray.org_y = origin.y(), ray.org_z = origin.z();
  ray.dir_x = dir.x(), ray.dir_y = dir.y(), ray.dir_z = dir.z();
  ray.tnear = tnear;
  ray.tfar = tfar;
  ray.mask = 0xFFFFFFFFu;
  ray.flags = 0;
  ray.time = 0.0f;
  ray.id = 0;
  return ray;
}

}  // namespace

EmbreeDevice::EmbreeDevice(const char* config) {
  device_ = rtcNewDevice(config);
  if (device_ == nullptr)
    throw std::runtime_error(
        fmt::format("cannot create an Embree device (error {}); is libembree3 installed?",
                    static_cast<int>(rtcGetDeviceError(nullptr))));
  rtcSetDeviceErrorFunction(device_, error_callback, nullptr);
}

EmbreeDevice::~EmbreeDevice() {
  if (device_) rtcReleaseDevice(device_);
}

EmbreeDevice& EmbreeDevice::operator=(EmbreeDevice&& o) noexcept {
  if (this != &o) {
    if (device_) rtcReleaseDevice(device_);
    device_ = o.device_;
    o.device_ = nullptr;
  }
  return *this;
}

EmbreeScene::EmbreeScene(TriMesh mesh, const Eigen::Matrix4f& transform, std::shared_ptr<EmbreeDevice> device)
    : device_(device ? std::move(device) : std::make_shared<EmbreeDevice>()), mesh_(std::move(mesh)) {
  if (mesh_.triangles.empty() || mesh_.positions.empty())
    throw std::runtime_error("cannot build an Embree scene from an empty mesh (no triangles)");
  Eigen::Affine3f xf(transform);
  Eigen::Matrix3f nxf = xf.linear().inverse().transpose();
  for (auto& p : mesh_.positions) p = xf * p;
  for (auto& n : mesh_.normals) n = (nxf * n).normalized();
  RTCDevice dev = device_->get();
  scene_ = rtcNewScene(dev);
  check_device(dev, "creating a scene");
  RTCGeometry geom = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), mesh_.positions.size()));
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned), mesh_.triangles.size()));
  if (v == nullptr || idx == nullptr) {
    rtcReleaseGeometry(geom);
    rtcReleaseScene(scene_);
    throw std::runtime_error("Embree could not allocate the vertex/index buffers (out of memory?)");
  }
  for (size_t i = 0; i < mesh_.positions.size(); ++i)
    for (int k = 0; k < 3; ++k) v[3 * i + k] = mesh_.positions[i][k];
  const int nv = static_cast<int>(mesh_.positions.size());
  for (size_t i = 0; i < mesh_.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      int vi = mesh_.triangles[i][k];
      if (vi < 0 || vi >= nv) {
        rtcReleaseGeometry(geom);
        rtcReleaseScene(scene_);
        throw std::runtime_error(
            fmt::format("triangle {} references vertex {} of {}: corrupt mesh", i, vi, nv));
      }
      idx[3 * i + k] = static_cast<unsigned>(vi);
    }
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene_, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scene_);
  check_device(dev, "building the scene");
}

EmbreeScene::~EmbreeScene() {
  if (scene_) rtcReleaseScene(scene_);
}

Eigen::AlignedBox3f EmbreeScene::bounds() const {
  Eigen::AlignedBox3f box;
  for (const auto& p : mesh_.positions) box.extend(p);
  return box;
}

Hit EmbreeScene::intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float tnear,
                           float tfar) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray = make_ray(origin, dir, tnear, tfar);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context, &rh);
  Hit h;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
  h.hit = true;
  h.t = rh.ray.tfar;
  h.triangle = static_cast<int>(rh.hit.primID);
  h.b1 = rh.hit.u;
  h.b2 = rh.hit.v;
  h.position = origin + h.t * dir;
  const Eigen::Vector3i& tri = mesh_.triangles[h.triangle];
  const float b0 = 1.0f - h.b1 - h.b2;
  h.geometric_normal = (mesh_.positions[tri[1]] - mesh_.positions[tri[0]])
                           .cross(mesh_.positions[tri[2]] - mesh_.positions[tri[0]])
                           .normalized();
  h.shading_normal = h.geometric_normal;
  if (!mesh_.normals.empty()) {
    Eigen::Vector3f n =
        b0 * mesh_.normals[tri[0]] + h.b1 * mesh_.normals[tri[1]] + h.b2 * mesh_.normals[tri[2]];
    if (n.squaredNorm() > 1e-12f) h.shading_normal = n.normalized();
  }
  if (!mesh_.uvs.empty()) h.uv = b0 * mesh_.uvs[tri[0]] + h.b1 * mesh_.uvs[tri[1]] + h.b2 * mesh_.uvs[tri[2]];
  if (h.triangle < static_cast<int>(mesh_.triangle_material.size()))
    h.material = mesh_.triangle_material[h.triangle];
  if (h.triangle < static_cast<int>(mesh_.triangle_part.size())) h.part = mesh_.triangle_part[h.triangle];
  return h;
}

bool EmbreeScene::occluded(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float tnear,
                           float tfar) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray = make_ray(origin, dir, tnear, tfar);
  rtcOccluded1(scene_, &context, &ray);
  return ray.tfar < 0.0f;  // Embree sets tfar = -inf on a hit
}

std::vector<Hit> EmbreeScene::intersect_many(const std::vector<RayQuery>& rays, int threads) const {
  std::vector<Hit> hits(rays.size());
  const int chunk = 1024;
  const int chunks = static_cast<int>((rays.size() + chunk - 1) / chunk);
  parallel_rows(chunks, threads, [&](int c) {
    size_t end = std::min(rays.size(), static_cast<size_t>(c + 1) * chunk);
    for (size_t i = static_cast<size_t>(c) * chunk; i < end; ++i)
      hits[i] = intersect(rays[i].origin, rays[i].dir, rays[i].tnear, rays[i].tfar);
  });
  return hits;
}

void parallel_rows(int rows, int threads, const std::function<void(int row)>& fn) {
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::max(1, std::min(threads, rows));
  std::atomic<int> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&] {
    for (int r; (r = next.fetch_add(1)) < rows;) {
      try {
        fn(r);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        next.store(rows);
      }
    }
  };
  std::vector<std::thread> pool;
  for (int i = 1; i < threads; ++i) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace lorgnette::mesh
