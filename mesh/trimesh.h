// The in-memory triangle mesh every mesh consumer shares (glasses, heads for dataset synthesis,
// parametric frames): flat arrays, one material per triangle, named parts, textures as linear
// float images. Units are whatever `units_to_mm` says (glasses are canonicalised to millimetres).
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "host/util/image_io.h"

namespace lorgnette::mesh {

struct Material {
  std::string name;
  Eigen::Vector3f base_color{0.8f, 0.8f, 0.8f};  // linear RGB, multiplied with the texture
  float metallic = 0.0f;
  float roughness = 0.5f;
  float specular = 0.5f;      // Disney "specular" (0.5 = F0 of 4 %)
  float alpha = 1.0f;         // coverage (1 = opaque)
  float transmission = 0.0f;  // KHR_materials_transmission factor (lenses)
  float ior = 1.5f;
  Eigen::Vector3f tint{1.0f, 1.0f, 1.0f};  // transmitted colour (lens tint)
  int base_color_texture = -1;             // index into TriMesh::textures, or -1
  bool is_lens = false;
  // Light the surface gives off itself (linear RGB radiance, glTF's emissiveFactor): a window's daylight.
  // Renderers that light surfaces add it to the lit colour; 0 = none.
  Eigen::Vector3f emission{0.0f, 0.0f, 0.0f};
};

struct TriMesh {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;    // per vertex; empty = flat shading from geometry
  std::vector<Eigen::Vector2f> uvs;        // per vertex; empty = no texturing; glTF convention: (0, 0) =
                                           // top-left of the image, v down (mesh/texture.h samples it)
  std::vector<Eigen::Vector3i> triangles;  // vertex indices
  std::vector<int> triangle_material;      // per triangle, index into materials
  std::vector<int> triangle_part;          // per triangle, index into part_names
  std::vector<Material> materials;
  std::vector<Image> textures;  // linear RGB(A)
  std::vector<std::string> part_names;
  double units_to_mm = 1.0;  // multiply positions by this to get millimetres

  size_t vertex_count() const { return positions.size(); }
  size_t triangle_count() const { return triangles.size(); }
};

}  // namespace lorgnette::mesh
