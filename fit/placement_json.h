// placement.json (ARCHITECTURE.md), read and written here only: what `fit` writes and `render`,
// `bench`, the viewer and the Python module read — the 4x4
// transform from the frame's canonical millimetres to the scene, the scale and its policy, the
// metric estimates (mm per unit, PD), named 3D landmarks with uncertainty and residuals, views used,
// remaining penetration, the temple spread, seconds per stage and an overall ok flag. Versioned; the
// reader refuses newer versions and malformed files with a message naming the field. Only "version"
// and "transform" are required, so a hand-written placement (a transform, optionally the glasses
// and the temples) reads too; a relative glasses path is relative to the placement file
// (glasses_file()), for every reader.
#pragma once
#include <Eigen/Core>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "fit/temple_fit.h"

namespace lorgnette::fit {

struct FitResult;

struct PlacementFile {
  static constexpr int kVersion = 1;
  int version = kVersion;
  std::string glasses_path, glasses_hash;                   // hash: FNV-1a 64 of the file's bytes, hex
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
  // "checks" (optional): the fit's input checks and its verdict's tolerances (fit/input_checks.h),
  // {name: {"checked", "passed", "value", "limit", "reason"}}; null when absent.
  nlohmann::json checks;
};

// The "temples" object: {"hinge_l": [x,y,z], "hinge_r": [x,y,z], "spread_l_deg": a,
// "spread_r_deg": b, "ramp_mm": r} (mesh/temple_bend.h), plus the fit's per-side figures.
nlohmann::json temple_bend_to_json(const mesh::TempleBend& b);
// The spread of a placement (the whole placement.json object); no "temples" = none. Throws naming
// the bad field.
mesh::TempleBend temple_bend_from_placement(const nlohmann::json& placement);

// Content hash of a file (FNV-1a 64, hex); throws when it cannot be read.
std::string file_hash(const std::string& path);

PlacementFile make_placement_file(const FitResult& r, const std::string& glasses_path,
                                  const std::string& scale_policy);

nlohmann::json to_json(const PlacementFile& p);
PlacementFile placement_from_json(const nlohmann::json& j);  // throws naming the bad field

void write_placement(const std::string& path, const PlacementFile& p);  // atomic
PlacementFile read_placement(const std::string& path);                  // errors name the file

// The glasses file a placement names, a relative path taken from the placement file's folder; ""
// when it names none.
std::string glasses_file(const PlacementFile& p, const std::string& placement_path);

}  // namespace lorgnette::fit
