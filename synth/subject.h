// A synthetic subject: a textured mesh placed in the dataset frame, with what is known about it
// exactly (scale in millimetres, landmarks). Two sources: the procedural head (millimetres, all
// landmarks known, mm_per_unit exact) or a mesh file through the mesh loader (assumed +y up and
// facing +z as glTF heads are; mm_per_unit only when the caller states the file's unit).
// Dataset frame convention: the subject is centred near the origin and about one unit across, the
// size instant-ngp style NeRFs expect (aabb_scale 1 with the usual 0.33 scale).
#pragma once
#include <Eigen/Core>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "mesh/trimesh.h"
#include "synth/procedural_head.h"

namespace lorgnette::synth {

// Scene scale of procedural heads: a 150 mm wide head is 0.75 units across.
constexpr double kProceduralMmPerUnit = 200.0;

struct Subject {
  std::string source;  // "procedural" or the mesh file path
  mesh::TriMesh mesh;  // in its own units (procedural: millimetres, head frame)
  Eigen::Matrix4f mesh_to_dataset = Eigen::Matrix4f::Identity();
  std::optional<double> mm_per_unit;                 // millimetres per dataset unit, when known
  nlohmann::json params;                             // procedural parameters (null for files)
  std::map<std::string, Eigen::Vector3f> landmarks;  // dataset frame
  std::vector<Eigen::Vector3f> ibug68;               // dataset frame; empty when unknown
  Eigen::Vector3f look_at{0, 0, 0};                  // dataset frame: where the rig cameras look
  float frame_radius = 0.7f;                         // dataset units the views must contain around look_at
  // Where a room is placed around the subject (synth/room.h): the eye point in the dataset frame
  // and the room's scale (mm_per_unit when known, else assumed from the mesh's size).
  Eigen::Vector3f eye_point{0, 0, 0};
  double room_mm_per_unit = kProceduralMmPerUnit;
  // Sizes known exactly (procedural heads; null for mesh files), written into ground_truth.json:
  // iris_diameter_mm, pd_mm (pupil centres), face_width_temples_mm and temple_r/temple_l (dataset frame).
  nlohmann::json metric;
};

// with_body: the head also gets a neck and shoulders (synth/body.h), as a subject in a room needs.
Subject procedural_subject(const HeadParams& params, const HeadMeshOptions& options = {},
                           bool with_body = false);

// mm_per_mesh_unit: the file's unit in millimetres if known (the loader's glTF "metres" is not
// trusted: scanned heads are often stored at arbitrary scale). Throws on unreadable files.
Subject mesh_subject(const std::string& path, std::optional<double> mm_per_mesh_unit = std::nullopt);

Eigen::Vector3f transform_point(const Eigen::Matrix4f& m, const Eigen::Vector3f& p);

}  // namespace lorgnette::synth
