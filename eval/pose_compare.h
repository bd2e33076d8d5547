// Pose accuracy of a captured dataset against a reference transforms.json (the same photos posed by
// someone else): the best similarity (Umeyama on the camera centres, matched by file stem) maps our
// scene onto theirs; rotation error per camera is the angle of R_ref^T * R_align * R_ours, centre
// error is relative to the reference cameras' mean distance from their centroid.
#pragma once
#include <string>

namespace lorgnette::capture {

struct PoseAccuracy {
  size_t matched = 0;  // frames present in both
  double rotation_deg_mean = 0, rotation_deg_max = 0;
  double centre_rel_mean = 0, centre_rel_max = 0;  // fraction of the reference camera spread
  double scale = 1;                                // reference units per scene unit
  // Mean residual rotation in the camera frame (axis * angle, degrees; x right, y up, z back): a
  // constant residual (mean norm close to rotation_deg_mean) comes from the intrinsics, e.g. a
  // different principal point tilts every camera the same way, not from the poses.
  double residual_camera_deg[3] = {0, 0, 0};
};

// `dataset`: folder with our transforms.json; `reference`: a transforms.json file. Throws when
// fewer than 3 frames match (a similarity needs 3 non-collinear centres).
PoseAccuracy compare_poses(const std::string& dataset, const std::string& reference);

}  // namespace lorgnette::capture
