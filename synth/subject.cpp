// Subjects for dataset synthesis; see subject.h.
#include "synth/subject.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <stdexcept>

#include "mesh/loader.h"
#include "synth/body.h"
#include "synth/room.h"

namespace lorgnette::synth {

Eigen::Vector3f transform_point(const Eigen::Matrix4f& m, const Eigen::Vector3f& p) {
  return m.topLeftCorner<3, 3>() * p + m.topRightCorner<3, 1>();
}

Subject procedural_subject(const HeadParams& params, const HeadMeshOptions& options, bool with_body) {
  ProceduralHead head = make_procedural_head(params, options);
  if (with_body) {
    append_mesh(head.mesh, make_neck_and_shoulders(params), Eigen::Matrix4f::Identity());
    head.mesh.units_to_mm = 1.0;
  }
  Subject s;
  s.source = "procedural";
  s.mm_per_unit = kProceduralMmPerUnit;
  s.mesh_to_dataset.topLeftCorner<3, 3>() *= float(1.0 / kProceduralMmPerUnit);
  nlohmann::json pj = head.params;
  s.params = pj;
  for (const auto& [name, p] : head.landmarks) s.landmarks[name] = transform_point(s.mesh_to_dataset, p);
  for (const auto& p : head.ibug) s.ibug68.push_back(transform_point(s.mesh_to_dataset, p));
  auto dataset_point = [&](const Eigen::Vector3f& p) {
    Eigen::Vector3f q = transform_point(s.mesh_to_dataset, p);
    return std::vector<float>{q.x(), q.y(), q.z()};
  };
  // Pupils are painted at the eye centres, which lie eye_distance apart in the frontal plane.
  s.metric = {{"iris_diameter_mm", params.iris_diameter},
              {"pd_mm", params.eye_distance},
              {"face_width_temples_mm", head.temple_width()},
              {"temple_r", dataset_point(head.temple_r)},
              {"temple_l", dataset_point(head.temple_l)}};
  // Frame the head from the crown to just below the chin (the neck may leave the picture).
  const float top = params.crown_height, bottom = -params.face_length - 20.0f;
  s.look_at = Eigen::Vector3f(0, 0.5f * (top + bottom), 0) / float(kProceduralMmPerUnit);
  s.frame_radius = (0.5f * (top - bottom) + 12.0f) / float(kProceduralMmPerUnit);
  s.mesh = std::move(head.mesh);
  return s;
}

Subject mesh_subject(const std::string& path, std::optional<double> mm_per_mesh_unit) {
  if (mm_per_mesh_unit && !(*mm_per_mesh_unit > 0))
    throw std::runtime_error(
        fmt::format("mesh unit must be a positive number of millimetres, got {}", *mm_per_mesh_unit));
  Subject s;
  s.source = path;
  s.mesh = mesh::load_mesh(path);
  Eigen::AlignedBox3f box;
  for (const auto& p : s.mesh.positions) box.extend(p);
  const float extent = box.sizes().maxCoeff();
  if (!(extent > 0))
    throw std::runtime_error(fmt::format("mesh '{}' has no extent (all vertices coincide)", path));
  // Centre the bounding box and scale its largest side to 1.5 units.
  const float scale = 1.5f / extent;
  s.mesh_to_dataset.topLeftCorner<3, 3>() *= scale;
  s.mesh_to_dataset.topRightCorner<3, 1>() = -scale * box.center();
  if (mm_per_mesh_unit) s.mm_per_unit = *mm_per_mesh_unit / scale;
  // Unknown scale: assume a bust, about 480 mm along its largest side (the team's scan: 486 mm).
  s.room_mm_per_unit = s.mm_per_unit ? *s.mm_per_unit : 480.0 / 1.5;
  s.eye_point = Eigen::Vector3f(0, 0.12f * scale * box.sizes().y(), 0);
  s.look_at = Eigen::Vector3f::Zero();
  Eigen::Vector3f half = 0.5f * scale * box.sizes();
  s.frame_radius = 1.05f * std::max(half.x(), half.y());
  return s;
}

}  // namespace lorgnette::synth
