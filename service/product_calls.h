// The only place the service calls the product's capture, train and fit: each stage's work as one
// function over folders, built from JobSettings through the same owners the CLI uses (CaptureOptions,
// nerf::TrainJob with capture::apply_subject_box, fit::FitSettings -> fit_options -> run_fit_job,
// render::OrbitSettings / RenderSettings -> plan_model_orbit / render_options).
// Kept in one small file so it can move to the shared request owners (TrainSettings -> TrainJob)
// in one change.
#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "host/cl/runtime.h"
#include "service/job_settings.h"

namespace lorgnette::service {

// The capture's input in its upload folder: the one video file, or the folder of photos. Throws
// with what to upload when the folder holds neither.
std::filesystem::path capture_input(const std::filesystem::path& upload_dir);

// capture::run_capture from `input` into `output_dir` (a new, empty folder). Throws the product's
// message (e.g. too few matches: what to film differently).
void capture_dataset(const std::filesystem::path& input, const std::filesystem::path& output_dir,
                     const JobSettings& settings);

// Trains on the dataset and writes the snapshot to `model_file`; `on_fraction` gets the share of the
// step budget done (0..1). Throws when training diverges; returns early when interrupted() (the
// caller must then discard the folder). The training checkpoint goes to `checkpoint` every
// settings.train_snapshot_seconds and at the end; a matching one there is resumed from
// (host/nerf/train_resume.h). The caller removes it (nerf::remove_checkpoints) once the model is in
// place.
void train_model(cl::Runtime& rt, const std::filesystem::path& dataset_dir,
                 const std::filesystem::path& model_file, const std::filesystem::path& checkpoint,
                 const JobSettings& settings, const std::function<void(double)>& on_fraction);

// Fits the frame file `glasses` on the model and writes placement.json into `output_dir`.
// Returns whether the fit passed its own checks (placement.json's `ok`).
bool fit_frame(cl::Runtime& rt, const std::filesystem::path& model_file,
               const std::filesystem::path& dataset_dir, const std::string& glasses,
               const std::filesystem::path& output_dir, const JobSettings& settings);

// The try-on views of one fitted frame: an orbit of settings.tryon_views images (view_NN.jpg,
// settings.tryon_size square) framing the head (fit/head_framing.h) within the directions the
// capture saw, the frame placed by `placement_file`, rendered through the RenderSettings /
// OrbitSettings owners as `lorgnette render --orbit --placement` does. Returns the file names.
std::vector<std::string> render_tryon_views(cl::Runtime& rt, const std::filesystem::path& model_file,
                                            const std::string& glasses,
                                            const std::filesystem::path& placement_file,
                                            const std::filesystem::path& output_dir,
                                            const JobSettings& settings);

}  // namespace lorgnette::service
