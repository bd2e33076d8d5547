// `lorgnette capture`: from a phone video, a folder of photos, or an existing COLMAP model to a
// posed dataset (transforms.json + images/) with the COLMAP workspace kept in colmap/ and a
// capture_report.json saying what was dropped and why, the warnings, and the time of each stage.
#pragma once
#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "capture/colmap_runner.h"
#include "capture/colmap_to_transforms.h"
#include "capture/frame_filter.h"
#include "capture/frame_source.h"
#include "fit/head_box.h"
#include "host/nerf/view_range.h"

namespace lorgnette::capture {

struct CaptureOptions {
  std::string input;   // video file, image folder, or folder with a COLMAP model
  std::string output;  // dataset folder (created; must be new, empty, or a previous capture and `force`)
  bool force = false;  // replace a previous capture in `output` (its images/, colmap/, transforms.json)
  FrameOptions frames;
  ColmapSettings colmap;
  bool blur_filter = true;
  bool blink_filter = true;
  BlurOptions blur;
  BlinkOptions blink;
  std::string landmark_model = "/usr/share/dlib/shape_predictor_68_face_landmarks.dat";
  ConvertOptions convert;
  // The subject box: the head box from landmarks triangulated on the photos (fit/head_box.h) when
  // faces are found, else the sparse-point box of the conversion.
  bool head_box = true;
  fit::HeadBoxOptions head;  // its detector model path is taken from landmark_model
  // The card step (capture/dataset_card.h): a held ID-1 card measured in the posed frames gives the
  // dataset's millimetres (scale.json).
  bool card = true;
};

struct DroppedFrame {
  std::string name, reason;
};

struct CaptureReport {
  std::string input_kind;       // "video", "images", "colmap-model"
  size_t source_frames = 0;     // frames in the video / images in the folder
  size_t candidate_frames = 0;  // after sampling and --max-frames
  size_t kept_frames = 0;       // after the blur and blink filters
  size_t faces_found = 0;       // frames where the blink filter found a face
  size_t registered = 0;        // frames with a pose
  size_t models = 0;            // COLMAP models (1 unless the capture fell apart)
  double mean_reprojection_error = 0;
  size_t subject_points = 0;
  Eigen::Vector3d aabb_min = Eigen::Vector3d::Zero(), aabb_max = Eigen::Vector3d::Zero();
  std::string aabb_from;  // "landmarks" (head box) or "sparse points"
  std::string aabb_note;  // how the box was made, or why the head box was not used
  // The directions the posed frames looked from about the subject box's centre (the range `train`
  // stores in the model), and what to film differently when the arc misses the ears ("" when not).
  std::optional<nerf::ViewRange> coverage;
  std::string coverage_advice;
  std::vector<DroppedFrame> dropped;
  std::vector<std::string> warnings;
  // The card step: {"searched": false} when disabled, else found, message, seconds, and with a card
  // mm_per_unit, mm_per_unit_uncertainty, frames and scale_file.
  nlohmann::json card = {{"searched", false}};
  std::vector<StageSeconds> seconds;  // per stage, in order
  std::string transforms_path, workspace;

  nlohmann::json to_json() const;
  nlohmann::json coverage_json() const;  // null when no frame was posed
};

// Runs the whole capture. Throws std::runtime_error with what is wrong and what to do.
CaptureReport run_capture(const CaptureOptions& options);

// The card step alone on a posed dataset (a capture, a synth output): fills report.card and its stage.
void measure_card_in_capture(const std::string& dataset_dir, CaptureReport& report);

// The frame filters on frames already in memory (exposed for tests): fills report.dropped/warnings
// and returns the indices of the frames kept.
std::vector<size_t> select_frames(const FrameSet& frames, const CaptureOptions& options,
                                  CaptureReport& report);

}  // namespace lorgnette::capture
