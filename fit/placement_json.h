// placement.json (docs/file-formats.md), read and written here only: what `fit` and the viewer write
// and `render`, `bench`, the viewer and the Python module read — the 4x4 transform from the frame's
// canonical millimetres to the scene, the scale and its policy, the metric estimates (mm per unit,
// PD), named 3D landmarks with uncertainty and residuals, views used, remaining penetration, the
// temple spread, a hand nudge, seconds per stage and an overall ok flag. Versioned; the reader
// refuses newer versions, malformed files and broken transforms (check_transform) with a message
// naming the field. Only "version" and "transform" are required, so a hand-written placement (a
// transform, optionally the glasses and the temples) reads too.
//
// Glasses paths: in memory a path as the process opens it (relative to its working directory); in
// the file a relative path is relative to the file's folder. write_placement() converts one way and
// read_placement() the other, so a placement written from one directory reads from any other.
#pragma once
#include <Eigen/Core>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "fit/fit_advice.h"
#include "fit/placement_transform.h"
#include "fit/temple_fit.h"

namespace lorgnette::fit {

// A hand adjustment of the placement (`lorgnette view`): the frame moved along its own canonical
// axes, up and forward in mm, tilted in degrees about its x axis through the bridge (positive: the
// lenses' bottoms towards the face). A placement's transform already includes its nudge.
struct PlacementNudge {
  double up_mm = 0, forward_mm = 0, tilt_deg = 0;
  bool zero() const { return up_mm == 0 && forward_mm == 0 && tilt_deg == 0; }
};
// The nudge as a transform in canonical mm: transform' = transform * nudge_matrix(n).
Eigen::Matrix4d nudge_matrix(const PlacementNudge& n);
// `first` then `then` as one nudge (both move in the y-z plane and turn about x, so the product of
// their matrices is a nudge again): nudge_matrix(result) = nudge_matrix(first) * nudge_matrix(then).
PlacementNudge combined_nudge(const PlacementNudge& first, const PlacementNudge& then);

struct PlacementFile {
  static constexpr int kVersion = 1;
  int version = kVersion;
  std::string glasses_path, glasses_hash;       // hash: FNV-1a 64 of the file's bytes, hex
  Transform transform = Transform::Identity();  // canonical mm -> scene
  std::string scale_policy = "stretch";         // as the frame was placed ("auto" is resolved by the fit)
  double scale = 1.0, mm_per_unit = 0.0, pd_mm = 0.0;
  // Where mm_per_unit came from ("card" | "iris" | "mean-face"; "" in files written before it) and
  // the 1-sigma uncertainties of the scale and of PD.
  std::string scale_source;
  double mm_per_unit_uncertainty = 0.0, pd_uncertainty_mm = 0.0;
  bool has_advice = false;  // "advice" (optional): the fit advice (fit_advice.h)
  FitAdvice advice;
  struct Landmark {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    double sigma_mm = 0.0;
    int views = 0;
  };
  std::map<std::string, Landmark> landmarks;
  std::map<std::string, double> residuals_px;
  int views_used = 0, views_total = 0;
  double penetration_mm = 0.0, contact_shift_mm = 0.0, front_penetration_mm = 0.0, tip_penetration_mm = 0.0;
  double contact_rise_mm = 0.0;  // how far the frame rode up the nose (fit/nose_rest.h)
  std::vector<std::pair<std::string, double>> seconds;
  std::vector<std::string> warnings;
  bool ok = false;
  // "temples" (optional; a file without it means rigid temples): hinges and spreads (the mesh's
  // TempleBend codec, mesh/temple_bend.h) plus per side "left"/"right": penetration_before_mm,
  // penetration_mm, points, clear.
  bool has_temples = false;
  TempleFitResult temples;
  bool has_nudge = false;  // "nudge": written by the viewer's save, included in `transform`
  PlacementNudge nudge;
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

nlohmann::json to_json(const PlacementFile& p);
PlacementFile placement_from_json(const nlohmann::json& j);  // throws naming the bad field

// Atomic; checks the transform first. A relative glasses path is stored relative to `path`'s folder.
void write_placement(const std::string& path, const PlacementFile& p);
// Errors name the file; a relative glasses path in it is resolved against its folder.
PlacementFile read_placement(const std::string& path);

// Why `glasses_path` is not the file the placement was fitted for (its content hash differs), or ""
// when it is, when the placement records no hash or when the file cannot be read (its loader says
// why). Front ends warn with it where the user reads warnings, and refuse where nobody would.
std::string glasses_mismatch(const PlacementFile& p, const std::string& glasses_path);

}  // namespace lorgnette::fit
