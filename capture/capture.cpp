// The capture pipeline: input -> frames -> selection -> images/ -> COLMAP -> transforms.json, with
// a timed stage each, and the report written beside the dataset (see capture.h).
#include "capture/capture.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "capture/dataset_card.h"
#include "capture/subject_framing.h"
#include "host/dataset/dataset.h"
#include "host/dataset/metric_scale.h"
#include "host/util/bounds.h"
#include "host/util/file_write.h"
#include "host/util/image_io.h"
#include "host/util/interrupt.h"
#include "host/util/name_list.h"
#include "host/util/output_folder.h"

namespace fs = std::filesystem;

namespace lorgnette::capture {
namespace {

class StageTimer {
 public:
  StageTimer(CaptureReport& r, std::string name)
      : report_(r), name_(std::move(name)), start_(std::chrono::steady_clock::now()) {}
  ~StageTimer() {
    report_.seconds.push_back(
        {name_, std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count()});
  }

 private:
  CaptureReport& report_;
  std::string name_;
  std::chrono::steady_clock::time_point start_;
};

// The output folder must be new, empty, or an earlier capture replaced with --force (the shared
// rule of host/util/output_folder.h; captures made before the marker existed are recognised by their
// capture_report.json). Checked before any work, so a slow frame selection never ends in a refusal.
// A capture replaces an earlier one in place: prepare_output clears only its images/ and colmap/.
const OutputOwner kCaptureOutput{"capture", "capture", "capture_report.json"};

// Clears an earlier capture's images/ and colmap/ (check_output_folder allowed it), so stale frames never
// reach COLMAP.
void prepare_output(const fs::path& out) {
  fs::remove_all(out / "images");
  fs::remove_all(out / "colmap");
  fs::create_directories(out / "images");
  fs::create_directories(out / "colmap");
}

void write_frames(const FrameSet& frames, const std::vector<size_t>& keep, const fs::path& dir) {
  for (size_t i : keep) {
    fs::path p = dir / frames.names[i];
    std::vector<uchar> bytes;  // encoded in memory: write_file_atomic checks every write
    if (!cv::imencode(p.extension().string(), frames.images[i], bytes, {cv::IMWRITE_JPEG_QUALITY, 95}))
      throw std::runtime_error(fmt::format("cannot encode frame '{}'", p.string()));
    write_file_atomic(p.string(),
                      std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  }
}

// COLMAP needs this many overlapping views, and so does a model given as input to be worth a dataset.
constexpr size_t kMinUsableFrames = 3;

// COLMAP model input: the images the model names but the image folder lacks are dropped from the
// model (and from its points' tracks), so no frame of the dataset points at a missing file. Throws
// when fewer than kMinUsableFrames remain.
void drop_missing_images(ColmapModel& model, const CaptureInput& in, CaptureReport& report) {
  std::vector<std::string> missing;
  const size_t named = model.images.size();
  for (auto it = model.images.begin(); it != model.images.end();) {
    if (fs::is_regular_file(in.image_dir / it->second.name)) {
      ++it;
      continue;
    }
    missing.push_back(it->second.name);
    report.dropped.push_back({it->second.name, fmt::format("image file not in '{}'", in.image_dir.string())});
    it = model.images.erase(it);
  }
  if (missing.empty()) return;
  for (auto& [id, p] : model.points)
    p.track.erase(std::remove_if(p.track.begin(), p.track.end(),
                                 [&](const auto& obs) { return !model.images.count(obs.first); }),
                  p.track.end());
  if (model.images.size() < kMinUsableFrames)
    throw std::runtime_error(fmt::format(
        "only {} of the {} images named by the COLMAP model in '{}' are in '{}' (missing: {}); at least "
        "{} are needed: put the photos the model was made from into '{}' (the model's image names are "
        "relative to it), or run `lorgnette capture` on the folder of photos to make a new model",
        model.images.size(), named, in.model_dir.string(), in.image_dir.string(), name_list(missing),
        kMinUsableFrames, in.image_dir.string()));
  report.warnings.push_back(
      fmt::format("{} of {} images named by the COLMAP model are not in '{}' ({}): "
                  "their frames are left out",
                  missing.size(), named, in.image_dir.string(), name_list(missing)));
}

// COLMAP model input: copy the registered images beside the transforms.
void copy_model_images(const ColmapModel& model, const CaptureInput& in, const fs::path& out) {
  for (const auto& [id, im] : model.images) {
    fs::path src = in.image_dir / im.name, dst = out / "images" / im.name;
    fs::create_directories(dst.parent_path());
    fs::copy_file(src, dst, fs::copy_options::overwrite_existing);
  }
}

// Replaces the sparse-point box of `scene` by the head box from landmarks when faces are found.
void choose_capture_box(const ColmapModel& model, const CaptureOptions& opt, ConvertedScene& scene,
                        CaptureReport& report) {
  report.aabb_from = "sparse points";
  report.aabb_note =
      fmt::format("robust box of {} sparse points around the cameras' focus", scene.subject_points);
  if (!opt.head_box) {
    report.aabb_note += " (head box disabled)";
    return;
  }
  StageTimer t(report, "head_box");
  std::vector<fit::PosedPhoto> photos;
  for (const auto& f : scene.frames) {
    Camera cam = camera_from_colmap(model.cameras.at(f.colmap_camera_id));
    dataset::set_camera_pose(cam, f.c2w);
    photos.push_back({cam, nullptr, (fs::path(opt.output) / f.file_path).string()});
  }
  fit::HeadBoxOptions ho = opt.head;
  ho.detector.model_path = opt.landmark_model;
  try {
    fit::HeadBox box = fit::estimate_head_box(photos, ho);
    scene.aabb_min = box.min;
    scene.aabb_max = box.max;
    report.aabb_from = "landmarks";
    report.aabb_note = box.summary();
    spdlog::info("capture: {}", box.summary());
    std::vector<Camera> cams;
    for (const auto& p : photos) cams.push_back(p.camera);
    if (FramingReport framing = check_head_framing(box, cams); framing.every_frame())
      report.warnings.push_back(framing.advice());
  } catch (const std::exception& e) {
    report.warnings.push_back(
        fmt::format("no head box, the sparse-point box is used instead: {}. If this is a person, film the "
                    "face itself, in focus, well lit and unobstructed, or `train` cannot separate them from "
                    "the room",
                    e.what()));
  }
}

// The yaw/pitch the posed frames covered about the subject box's centre (nerf::ViewRange, as `train`
// measures it), with a warning saying what to film differently when the ears were not seen.
void report_coverage(const ColmapModel& model, const ConvertedScene& scene, CaptureReport& report) {
  if (scene.frames.empty()) return;
  std::vector<Camera> cams;
  for (const auto& f : scene.frames) {
    Camera cam = camera_from_colmap(model.cameras.at(f.colmap_camera_id));
    dataset::set_camera_pose(cam, f.c2w);
    cams.push_back(cam);
  }
  Eigen::Vector3d c = 0.5 * (scene.aabb_min + scene.aabb_max);
  report.coverage = nerf::view_range_from_cameras(cams, {float(c.x()), float(c.y()), float(c.z())});
  report.coverage_advice = nerf::coverage_advice(*report.coverage);
  spdlog::info("capture: covered {}", report.coverage->summary());
  if (!report.coverage_advice.empty()) report.warnings.push_back(report.coverage_advice);
}

void convert_and_write(const ColmapModel& model, const CaptureOptions& opt, CaptureReport& report) {
  ConvertedScene scene;
  {
    StageTimer t(report, "convert");
    scene = convert_colmap_model(model, opt.convert);
  }
  choose_capture_box(model, opt, scene, report);
  write_capture_transforms(opt.output, model, scene);
  report.registered = scene.frames.size();
  report.mean_reprojection_error = scene.mean_reprojection_error;
  report.subject_points = scene.subject_points;
  report.aabb_min = scene.aabb_min;
  report.aabb_max = scene.aabb_max;
  report_coverage(model, scene, report);
  report.transforms_path = (fs::path(opt.output) / "transforms.json").string();
}

FrameSet read_frames(const CaptureInput& in, const CaptureOptions& opt, CaptureReport& report) {
  StageTimer t(report, "frames");
  FrameSet set = in.kind == InputKind::Video ? read_video_frames(in.path, opt.frames)
                                             : read_image_folder(in.image_dir, opt.frames);
  if (interrupted()) throw std::runtime_error("interrupted while reading frames");
  report.source_frames = set.source_frames;
  report.candidate_frames = set.images.size();
  return set;
}

}  // namespace

void measure_card_in_capture(const std::string& dataset_dir, CaptureReport& report) {
  StageTimer t(report, "card");
  DatasetCardResult r = measure_dataset_card(dataset_dir);
  report.card = {
      {"searched", true}, {"found", r.scale.found}, {"message", r.scale.message}, {"seconds", r.seconds}};
  if (r.scale.found) {
    report.card["mm_per_unit"] = r.scale.mm_per_unit;
    report.card["mm_per_unit_uncertainty"] = r.scale.uncertainty;
    report.card["frames"] = r.scale.frames;
    report.card["scale_file"] = (fs::path(dataset_dir) / dataset::kScaleFile).string();
    report.card["ignore_frames"] = r.ignore_frames;
    if (r.ignore_frames > 0)
      report.card["ignore_file"] = (fs::path(dataset_dir) / dataset::kIgnoreRegionsFile).string();
  }
  spdlog::info("capture: {}", r.scale.message);
  if (r.ignore_frames > 0)
    spdlog::info("capture: the card and its fingers are left out of training in {} frames ({})",
                 r.ignore_frames, dataset::kIgnoreRegionsFile);
}

nlohmann::json CaptureReport::coverage_json() const {
  if (!coverage) return nullptr;
  return {{"yaw_deg", {coverage->yaw_min, coverage->yaw_max}},
          {"pitch_deg", {coverage->pitch_min, coverage->pitch_max}},
          {"cameras", coverage->cameras},
          {"ear_to_ear", coverage_advice.empty()},
          {"needed_yaw_each_side_deg", nerf::kEarToEarYawDeg},
          {"advice", coverage_advice}};
}

nlohmann::json CaptureReport::to_json() const {
  nlohmann::json dropped_j = nlohmann::json::array(), seconds_j = nlohmann::json::object();
  for (const auto& d : dropped) dropped_j.push_back({{"frame", d.name}, {"reason", d.reason}});
  double total = 0;
  for (const auto& s : seconds) seconds_j[s.stage] = s.seconds, total += s.seconds;
  seconds_j["total"] = total;
  return {{"input_kind", input_kind},
          {"source_frames", source_frames},
          {"candidate_frames", candidate_frames},
          {"kept_frames", kept_frames},
          {"faces_found", faces_found},
          {"registered", registered},
          {"models", models},
          {"mean_reprojection_error_px", mean_reprojection_error},
          {"subject_points", subject_points},
          {"aabb", {{aabb_min.x(), aabb_min.y(), aabb_min.z()}, {aabb_max.x(), aabb_max.y(), aabb_max.z()}}},
          {"aabb_from", aabb_from},
          {"aabb_note", aabb_note},
          {"coverage", coverage_json()},
          {"card", card},
          {"dropped", dropped_j},
          {"warnings", warnings},
          {"seconds", seconds_j},
          {"transforms", transforms_path},
          {"workspace", workspace}};
}

namespace {
// The table's ranges (host/util/bounds.h), for `capture` and the service's captures alike, before
// the input is read.
void validate_numbers(const CaptureOptions& opt) {
  check_bound(bounds::kCaptureFps, opt.frames.fps);
  check_bound_or_zero(bounds::kCaptureMaxFrames, opt.frames.max_frames);
  check_bound_or_zero(bounds::kCaptureSide, opt.frames.max_side);
  check_bound(bounds::kMaxFeatures, opt.colmap.max_features);
}
}  // namespace

CaptureReport run_capture(const CaptureOptions& opt) {
  if (opt.output.empty()) throw std::runtime_error("no output folder: give -o DATASET");
  validate_numbers(opt);
  CaptureInput in = classify_input(opt.input);
  fs::path out = opt.output;
  check_output_folder(out, kCaptureOutput, opt.force, {in.path.string()});
  CaptureReport report;
  report.workspace = (out / "colmap").string();
  if (in.kind == InputKind::ColmapModel) {
    report.input_kind = "colmap-model";
    ColmapModel model = read_colmap_model(in.model_dir);
    report.source_frames = report.candidate_frames = model.images.size();
    drop_missing_images(model, in, report);
    report.kept_frames = model.images.size();
    prepare_output(out);
    copy_model_images(model, in, out);
    report.models = 1;
    convert_and_write(model, opt, report);
  } else {
    if (in.kind == InputKind::ImageFolder) find_colmap(opt.colmap);  // fail before the slow part
    report.input_kind = in.kind == InputKind::Video ? "video" : "images";
    FrameSet frames = read_frames(in, opt, report);
    std::vector<size_t> keep;
    {
      StageTimer t(report, "select");
      keep = select_frames(frames, opt, report);
    }
    report.kept_frames = keep.size();
    if (keep.size() < kMinUsableFrames)
      throw std::runtime_error(
          fmt::format("only {} usable frames: COLMAP needs at least {} overlapping "
                      "views (give more photos or a longer video)",
                      keep.size(), kMinUsableFrames));
    prepare_output(out);
    {
      StageTimer t(report, "write");
      write_frames(frames, keep, out / "images");
    }
    ColmapSettings colmap = opt.colmap;
    if (opt.frames.max_side > 0) colmap.max_image_size = opt.frames.max_side;
    ColmapResult cr = run_colmap(out / "images", out / "colmap", keep.size(), colmap);
    report.seconds.insert(report.seconds.end(), cr.seconds.begin(), cr.seconds.end());
    report.warnings.insert(report.warnings.end(), cr.warnings.begin(), cr.warnings.end());
    report.models = cr.models;
    convert_and_write(read_colmap_model(cr.model_dir), opt, report);
  }
  if (opt.card) {
    // The card only adds millimetres: a frame it cannot read costs the scale, never the capture.
    try {
      measure_card_in_capture(out.string(), report);
    } catch (const std::exception& e) {
      report.card = {{"searched", true}, {"found", false}, {"message", e.what()}};
      report.warnings.push_back(fmt::format("no card scale: {}", e.what()));
    }
  }
  for (const auto& w : report.warnings) spdlog::warn("{}", w);
  mark_output(out, kCaptureOutput);
  write_text_file_atomic((out / "capture_report.json").string(), report.to_json().dump(2) + "\n");
  return report;
}

}  // namespace lorgnette::capture
