// Ray tracing a TriMesh with Embree 3: an RAII device (one error callback that turns Embree errors
// into exceptions/log lines) and a scene that owns its geometry (commit-attach-release, as in the
// Embree 3.13 minimal tutorial). The scene keeps a copy of the mesh with the placement transform
// applied, so hits report world-space positions and normals, the uv and the material directly.
// intersect()/occluded() are thread-safe; trace_rows() runs a per-row function on a few threads.
#pragma once
#include <embree3/rtcore.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <functional>
#include <limits>
#include <memory>

#include "mesh/trimesh.h"

namespace lorgnette::mesh {

// Move-only owner of an RTCDevice.
class EmbreeDevice {
 public:
  explicit EmbreeDevice(const char* config = "threads=1");  // the surface pass threads itself
  ~EmbreeDevice();
  EmbreeDevice(EmbreeDevice&& o) noexcept : device_(o.device_) { o.device_ = nullptr; }
  EmbreeDevice& operator=(EmbreeDevice&& o) noexcept;
  EmbreeDevice(const EmbreeDevice&) = delete;
  EmbreeDevice& operator=(const EmbreeDevice&) = delete;
  RTCDevice get() const { return device_; }

 private:
  RTCDevice device_ = nullptr;
};

struct Hit {
  bool hit = false;
  float t = 0.0f;        // ray parameter (distance when the direction is unit length)
  int triangle = -1;     // index into mesh().triangles
  float b1 = 0, b2 = 0;  // barycentrics of vertices 1 and 2 (Embree's u, v)
  Eigen::Vector3f position{0, 0, 0};
  Eigen::Vector3f geometric_normal{0, 0, 0};  // unit, from the triangle winding
  Eigen::Vector3f shading_normal{0, 0, 0};    // unit, interpolated vertex normal (= geometric if none)
  Eigen::Vector2f uv{0, 0};
  int material = -1;  // index into mesh().materials
  int part = -1;      // index into mesh().part_names
};

struct RayQuery {
  Eigen::Vector3f origin, dir;
  float tnear = 0.0f, tfar = std::numeric_limits<float>::infinity();
};

class EmbreeScene {
 public:
  // `transform` maps the mesh's coordinates to world (scene) coordinates, scale included.
  EmbreeScene(TriMesh mesh, const Eigen::Matrix4f& transform = Eigen::Matrix4f::Identity(),
              std::shared_ptr<EmbreeDevice> device = nullptr);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  Hit intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float tnear = 0.0f,
                float tfar = std::numeric_limits<float>::infinity()) const;
  bool occluded(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float tnear = 0.0f,
                float tfar = std::numeric_limits<float>::infinity()) const;
  // Many rays, split over `threads` worker threads (0 = hardware concurrency).
  std::vector<Hit> intersect_many(const std::vector<RayQuery>& rays, int threads = 0) const;

  const TriMesh& mesh() const { return mesh_; }  // transformed to world coordinates
  Eigen::AlignedBox3f bounds() const;

 private:
  std::shared_ptr<EmbreeDevice> device_;
  RTCScene scene_ = nullptr;
  TriMesh mesh_;
};

// Runs fn(row) for row in [0, rows) on `threads` threads (0 = hardware concurrency), rows handed
// out dynamically; the first exception thrown by fn is rethrown on the caller's thread.
void parallel_rows(int rows, int threads, const std::function<void(int row)>& fn);

}  // namespace lorgnette::mesh
