// A ViewSource over a textured triangle mesh (a head scan such as Lee Perry-Smith, or a synthetic
// head), ray cast with Embree through the mesh module: views shaded with the colour map under a
// head-mounted light, density as an inside indicator. It gives the fit exact geometry for tests and
// the stability study, with no NeRF in the loop; ground truth comes from cast().
#pragma once
#include <memory>
#include <optional>
#include <string>

#include "fit/view_source.h"
#include "mesh/embree_scene.h"

namespace lorgnette::fit {

struct MeshShading {
  float ambient = 0.45f;  // share of light that does not depend on the normal
  float diffuse = 0.55f;  // Lambert term from a light at the camera
  Eigen::Vector3f background{1.0f, 1.0f, 1.0f};
  int threads = 0;  // 0 = hardware concurrency
  // No UV option here: TriMesh UVs are in the glTF convention, the loader fixes files that break it
  // (mesh::LoadOptions::flip_v), so every consumer of a mesh samples its textures the same way.
};

class MeshViewSource : public ViewSource {
 public:
  // `mesh_to_scene` places the mesh in the scene (scale included). Throws when the mesh is empty.
  MeshViewSource(mesh::TriMesh mesh, const Eigen::Matrix4f& mesh_to_scene = Eigen::Matrix4f::Identity(),
                 std::optional<ViewPrior> prior = std::nullopt, MeshShading shading = {});
  static std::unique_ptr<MeshViewSource> load(const std::string& path,
                                              std::optional<ViewPrior> prior = std::nullopt,
                                              MeshShading shading = {});

  Image render(const Camera& cam) override;
  // 1e4 inside the (closed parts of the) mesh, 0 outside: inside when the nearest hit of at least two
  // of three fixed, non-axis-aligned rays is a back face.
  std::vector<float> density(const std::vector<Eigen::Vector3f>& points) override;
  Bounds bounds() const override;
  ViewPrior prior() const override;
  bool hard_surface() const override { return true; }

  // First surface hit along a ray (scene units); for ground-truth landmarks.
  mesh::Hit cast(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir) const;
  const mesh::EmbreeScene& scene() const { return *scene_; }

 private:
  std::unique_ptr<mesh::EmbreeScene> scene_;
  std::optional<ViewPrior> prior_;
  MeshShading shading_;
};

}  // namespace lorgnette::fit
