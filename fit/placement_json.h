// placement.json (ARCHITECTURE.md): what `fit` writes and `render` / the viewer read — the 4x4
// transform from the frame's canonical millimetres to the scene, the scale and its policy, the
// metric estimates (mm per unit, PD), named 3D landmarks with uncertainty and residuals, views used,
// remaining penetration, the temple spread, seconds per stage and an overall ok flag. Versioned; read() refuses newer
// versions and malformed files with a message naming the field.
#pragma once
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "fit/temple_fit.h"

namespace lorgnette::fit {

struct FitResult;

struct PlacementFile {
  static constexpr int kVersion = 1;
  int version = kVersion;
  std::string glasses_path, glasses_hash;  // hash: FNV-1a 64 of the file's bytes, hex
  Eigen::Matrix4d transform = Eigen::Matrix4d::Identity();  // canonical mm -> scene
  std::string scale_policy = "stretch";
  double scale = 1.0, mm_per_unit = 0.0, pd_mm = 0.0;
  struct Landmark {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    double sigma_mm = 0.0;
    int views = 0;
  };
  std::map<std::string, Landmark> landmarks;
  std::map<std::string, double> residuals_px;
  int views_used = 0, views_total = 0;
  double penetration_mm = 0.0, contact_shift_mm = 0.0, front_penetration_mm = 0.0, tip_penetration_mm = 0.0;
  std::vector<std::pair<std::string, double>> seconds;
  std::vector<std::string> warnings;
  bool ok = false;
  // "temples" (optional; a file without it means rigid temples): hinges and spreads (the mesh's
  // TempleBend codec, mesh/temple_bend.h) plus per side "left"/"right": penetration_before_mm,
  // penetration_mm, points, clear.
  bool has_temples = false;
  TempleFitResult temples;
};

// Content hash of a file (FNV-1a 64, hex); throws when it cannot be read.
std::string file_hash(const std::string& path);

PlacementFile make_placement_file(const FitResult& r, const std::string& glasses_path, const std::string& scale_policy);

nlohmann::json to_json(const PlacementFile& p);
PlacementFile placement_from_json(const nlohmann::json& j);  // throws naming the bad field

void write_placement(const std::string& path, const PlacementFile& p);  // atomic
PlacementFile read_placement(const std::string& path);

}  // namespace lorgnette::fit
