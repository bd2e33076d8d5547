// Dataset synthesis: renders a Subject from a sphere-cap camera rig and writes a training dataset
//   transforms.json     instant-ngp / nerfstudio (exact intrinsics and poses; per-frame depth_path)
//   images/NNNN.png     RGBA, straight alpha (transparent background) or opaque on a chosen colour
//   depth/NNNN.exr      1 channel float: distance along the unit pixel-centre ray, dataset units,
//                       +inf where the ray misses the subject
//   ground_truth.json   source (mesh path or "procedural" + seed + params), mesh_to_dataset (4x4),
//                       mm_per_unit (null when unknown), landmarks and the 68 iBUG points in the
//                       dataset frame, per-view yaw/pitch, lighting and render settings
// The whole directory appears atomically (see staged_dir.h).
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "synth/camera_rig.h"
#include "synth/studio_render.h"
#include "synth/subject.h"

namespace lorgnette::synth {

struct SynthOptions {
  int views = 24;
  int width = 256, height = 256;
  float yaw_min_deg = -35.0f, yaw_max_deg = 35.0f;
  float pitch_min_deg = -12.0f, pitch_max_deg = 18.0f;
  uint64_t seed = 0;                          // camera placement seed
  std::optional<Eigen::Vector3f> background;  // linear RGB; empty = transparent
  int samples_per_axis = 3;
  float camera_distance = 3.0f;               // dataset units from the subject's look-at point
  bool force = false;                         // replace a non-empty output directory
  StudioLighting lighting;
  std::function<void(int done, int total)> progress;  // called after each view
};

struct SynthReport {
  std::string directory;
  int views = 0;
  double seconds = 0.0;         // total wall time (rendering + writing)
  double render_seconds = 0.0;  // ray tracing only
};

// The rig the options describe, aimed at the subject.
RigOptions rig_for(const Subject& subject, const SynthOptions& options);

// Throws std::runtime_error (nothing is left under out_dir) on bad options, unwritable output or
// Ctrl-C (host/util/interrupt.h).
SynthReport synthesize_dataset(const Subject& subject, const std::string& out_dir, const SynthOptions& options);

}  // namespace lorgnette::synth
