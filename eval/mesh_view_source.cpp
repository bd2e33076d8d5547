// Embree-backed ViewSource (see mesh_view_source.h).
#include "eval/mesh_view_source.h"

#include <algorithm>
#include <stdexcept>

#include "fit/camera_math.h"
#include "mesh/loader.h"
#include "mesh/texture.h"

namespace lorgnette::fit {

MeshViewSource::MeshViewSource(mesh::TriMesh m, const Eigen::Matrix4f& mesh_to_scene,
                               std::optional<ViewPrior> prior, MeshShading shading)
    : prior_(std::move(prior)), shading_(shading) {
  if (m.triangles.empty()) throw std::runtime_error("MeshViewSource: the mesh has no triangles");
  scene_ = std::make_unique<mesh::EmbreeScene>(std::move(m), mesh_to_scene);
}

std::unique_ptr<MeshViewSource> MeshViewSource::load(const std::string& path, std::optional<ViewPrior> prior,
                                                     MeshShading shading) {
  return std::make_unique<MeshViewSource>(mesh::load_mesh(path), Eigen::Matrix4f::Identity(),
                                          std::move(prior), shading);
}

mesh::Hit MeshViewSource::cast(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir) const {
  return scene_->intersect(origin, dir.normalized());
}

Image MeshViewSource::render(const Camera& cam) {
  const int w = int(cam.width), h = int(cam.height);
  std::vector<mesh::RayQuery> rays(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      Ray r = camera_ray(cam, Eigen::Vector2d(x + 0.5, y + 0.5));
      rays[size_t(y) * w + x] = {r.origin.cast<float>(), r.dir.cast<float>()};
    }
  std::vector<mesh::Hit> hits = scene_->intersect_many(rays, shading_.threads);
  const mesh::TriMesh& m = scene_->mesh();
  Image img(w, h, 3);
  for (size_t i = 0; i < hits.size(); ++i) {
    Eigen::Vector3f c = shading_.background;
    const mesh::Hit& hit = hits[i];
    if (hit.hit) {
      Eigen::Vector3f albedo(0.7f, 0.6f, 0.55f);
      if (hit.material >= 0 && hit.material < int(m.materials.size())) {
        const mesh::Material& mat = m.materials[hit.material];
        albedo = mat.base_color;
        if (mat.base_color_texture >= 0 && !m.uvs.empty())
          albedo =
              albedo.cwiseProduct(mesh::sample_texture(m.textures[mat.base_color_texture], hit.uv).head<3>());
      }
      float lambert = std::abs(hit.shading_normal.dot(rays[i].dir));  // light at the camera
      c = albedo * (shading_.ambient + shading_.diffuse * lambert);
    }
    for (int k = 0; k < 3; ++k) img.pixels[i * 3 + k] = c[k];
  }
  return img;
}

std::vector<float> MeshViewSource::density(const std::vector<Eigen::Vector3f>& points) {
  static const Eigen::Vector3f dirs[3] = {Eigen::Vector3f(0.48f, 0.80f, 0.36f).normalized(),
                                          Eigen::Vector3f(-0.70f, -0.10f, 0.71f).normalized(),
                                          Eigen::Vector3f(0.15f, -0.60f, -0.79f).normalized()};
  std::vector<mesh::RayQuery> rays;
  rays.reserve(points.size() * 3);
  for (const auto& p : points)
    for (const auto& d : dirs) rays.push_back({p, d});
  std::vector<mesh::Hit> hits = scene_->intersect_many(rays, shading_.threads);
  std::vector<float> out(points.size(), 0.0f);
  for (size_t i = 0; i < points.size(); ++i) {
    int back = 0;
    for (int k = 0; k < 3; ++k) {
      const mesh::Hit& h = hits[i * 3 + k];
      if (h.hit && h.geometric_normal.dot(rays[i * 3 + k].dir) > 0.0f) ++back;
    }
    out[i] = back >= 2 ? 1e4f : 0.0f;
  }
  return out;
}

Bounds MeshViewSource::bounds() const {
  Eigen::AlignedBox3f b = scene_->bounds();
  Bounds out;
  out.min = b.min();
  out.max = b.max();
  return out;
}

ViewPrior MeshViewSource::prior() const { return prior_ ? *prior_ : ViewPrior{}; }

}  // namespace lorgnette::fit
