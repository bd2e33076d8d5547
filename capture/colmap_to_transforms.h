// Converts a COLMAP sparse model to the instant-ngp / nerfstudio transforms.json convention:
// OPENCV intrinsics, OpenGL-style camera-to-world matrices (camera looks down -z, +y up), the world
// rotated so the mean camera up is +z (as instant-ngp's colmap2nerf), and the scene centred and
// scaled on the subject: a robust bounding box of the sparse points the cameras look at (the head
// for a head capture) becomes the "aabb" field, so training can ignore the room behind.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "capture/colmap_model.h"
#include "common/camera_types.h"

namespace lorgnette::capture {

struct ConvertOptions {
  // Points within this fraction of the median camera-to-focus distance of the focus point (where
  // the optical axes meet) are the subject; the rest is background.
  double subject_radius_fraction = 0.5;
  double box_percentile = 0.03;          // per-axis robust extent: [p, 1 - p] quantiles of subject points
  double box_padding = 0.15;             // grow the box by this fraction of its extent on each side
  size_t min_track_length = 3;           // points seen by fewer images are too noisy for the box
  std::string image_prefix = "images/";  // file_path = prefix + COLMAP image name
};

struct ConvertedFrame {
  std::string file_path;
  uint32_t colmap_image_id = 0;
  uint32_t colmap_camera_id = 0;
  Eigen::Matrix4d c2w = Eigen::Matrix4d::Identity();  // scene frame, OpenGL camera axes
};

struct ConvertedScene {
  std::vector<ConvertedFrame> frames;  // sorted by file_path
  // p_scene = scale * rotation * p_colmap + translation (as one 4x4 similarity).
  Eigen::Matrix4d colmap_to_scene = Eigen::Matrix4d::Identity();
  double scale = 1;
  Eigen::Vector3d aabb_min, aabb_max;  // subject box in the scene frame
  size_t subject_points = 0;           // sparse points that defined the box
  double mean_reprojection_error = 0;  // pixels, mean over the sparse points
};

// Throws for an empty model or a camera model with no OPENCV equivalent (fisheye models).
ConvertedScene convert_colmap_model(const ColmapModel& model, const ConvertOptions& options = {});

// The shared Camera (kernels/common/camera_types.h) of a COLMAP camera: OPENCV parameters from
// any pinhole/radial/OPENCV model; throws for fisheye models and FULL_OPENCV with k3.. != 0.
Camera camera_from_colmap(const ColmapCamera& camera);

// Writes `dir`/transforms.json through host/dataset's writer: intrinsics (shared when all cameras
// agree), frames, and the extra keys "aabb" ([[min], [max]] of the subject box in scene units),
// "colmap_to_scene" (4x4), "scene_scale", "up" ([0, 0, 1]) and "mean_reprojection_error_px".
void write_capture_transforms(const std::string& dir, const ColmapModel& model, const ConvertedScene& scene);

// OpenGL camera-to-world of a COLMAP world-to-camera pose (no world change), and its inverse.
Eigen::Matrix4d colmap_pose_to_opengl_c2w(const Eigen::Vector4d& qvec, const Eigen::Vector3d& tvec);
void opengl_c2w_to_colmap_pose(const Eigen::Matrix4d& c2w, Eigen::Vector4d& qvec, Eigen::Vector3d& tvec);

}  // namespace lorgnette::capture
