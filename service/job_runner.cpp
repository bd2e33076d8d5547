// The stages of one job and its progress reports (job_runner.h).
#include "service/job_runner.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <sys/file.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <optional>
#include <stdexcept>

#include "fit/placement_json.h"
#include "host/nerf/train_resume.h"
#include "host/util/image_io.h"
#include "host/util/interrupt.h"
#include "service/job_folder.h"
#include "service/job_settings.h"
#include "service/product_calls.h"
#include "service/progress.h"
#include "service/stage.h"
#include "viewer/catalogue.h"

namespace fs = std::filesystem;

namespace lorgnette::service {
namespace {

// Shares of the whole job's progress bar: capture, train, fit (the fit share split over frames).
constexpr double kCaptureEnd = 20.0, kTrainEnd = 80.0, kFitEnd = 100.0;

struct Interrupted : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Reporter {
 public:
  explicit Reporter(const JobFolder& f) : folder_(f), start_(Clock::now()) {}
  // Writes at most twice a second unless `force` (stage changes and the end are always written).
  void update(const std::string& stage, double percent, const std::string& message, bool force = true) {
    const auto now = Clock::now();
    if (stage != p_.stage) end_stage(now), stage_start_ = now, force = true;
    if (!force && now - last_ < std::chrono::milliseconds(500)) return;
    last_ = now;
    p_.stage = stage, p_.percent = percent, p_.message = message;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    p_.eta_seconds = percent > 1.0 && percent < 100.0 ? elapsed * (100.0 - percent) / percent : -1.0;
    write_progress(folder_.progress(), p_);
  }
  void finish(const std::string& state, const std::string& message) {
    p_.state = state, p_.message = message, p_.eta_seconds = state == "finished" ? 0.0 : -1.0;
    if (state == "finished") p_.percent = 100.0, end_stage(Clock::now());
    write_progress(folder_.progress(), p_);
  }
  nlohmann::json& artifacts() { return p_.artifacts; }

 private:
  using Clock = std::chrono::steady_clock;
  // The stage in progress is complete: its seconds into progress.json (a failed one is not counted).
  void end_stage(Clock::time_point now) {
    if (!p_.stage.empty())
      p_.stage_seconds[p_.stage] = std::chrono::duration<double>(now - stage_start_).count();
  }
  const JobFolder& folder_;
  Progress p_;
  Clock::time_point start_, last_{}, stage_start_{};
};

void check_interrupt(const char* where) {
  if (interrupted()) throw Interrupted(fmt::format("stopped before {}; the job can run again", where));
}

void capture_stage(const JobFolder& f, const JobSettings& s, Reporter& r) {
  check_interrupt("the capture");
  r.update("capture", 0.0, "finding the camera of every frame");
  run_stage(f.dataset(), [&](const fs::path& tmp) { capture_dataset(capture_input(f.upload()), tmp, s); });
  r.artifacts()["dataset"] = "dataset/transforms.json";
}

void train_stage(const JobFolder& f, const JobSettings& s, cl::Runtime& rt, Reporter& r) {
  check_interrupt("training");
  r.update("train", kCaptureEnd, "training the head's model");
  // The checkpoint lives outside the stage's temporary folder: a run killed or stopped during
  // training leaves it, and the next run resumes from it (the temporary folder is made again).
  run_stage(f.model_dir(), [&](const fs::path& tmp) {
    train_model(rt, f.dataset(), tmp / f.model().filename(), f.train_checkpoint(), s, [&](double done) {
      r.update("train", kCaptureEnd + (kTrainEnd - kCaptureEnd) * std::min(done, 1.0),
               "training the head's model", false);
    });
    if (interrupted()) throw Interrupted("stopped during training; the job can run again");
  });
  // Only once the model is in place (a kill before this resumes at the last step, trains nothing more).
  nerf::remove_checkpoints(f.train_checkpoint().string());
  r.artifacts()["model"] = "model/head.lnerf";
}

// What a frame's cached fit and views were made from: the model's and the frame file's content
// hashes. A fit folder made from another model (retrained) or another file under the same name is
// stale and is made again; one made from these is complete and reused.
nlohmann::json made_from(const std::string& model_hash, const std::string& glasses) {
  return {{"model_hash", model_hash}, {"glasses_hash", fit::file_hash(glasses)}};
}

void drop_stale_fit(const fs::path& dir, const nlohmann::json& expected) {
  if (!fs::exists(dir)) return;
  std::ifstream in(dir / "made_from.json");
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (!j.is_discarded() && j == expected) return;
  spdlog::info("fit '{}' was made from another model or frame file: making it again", dir.string());
  fs::remove_all(dir);
}

// Fits one frame and renders its try-on views, or reuses its cached fit; returns the reason when
// the frame cannot be fitted (its file does not load, no face is found with it, ...): a frame's
// failure is that frame's, and the job goes on with the others. A stop (SIGTERM) passes on.
std::optional<std::string> fit_one(const JobFolder& f, const JobSettings& s, cl::Runtime& rt,
                                   const viewer::FrameEntry& frame, const std::string& model_hash) {
  try {
    const std::string key = frame_key(frame.name);
    const nlohmann::json stamp = made_from(model_hash, frame.path);
    drop_stale_fit(f.fit_dir(key), stamp);
    run_stage(f.fit_dir(key), [&](const fs::path& tmp) {
      fit_frame(rt, f.model(), f.dataset(), frame.path, tmp, s);
      const auto names = render_tryon_views(rt, f.model(), frame.path, tmp / "placement.json", tmp, s);
      write_text_file_atomic((tmp / "views.json").string(), nlohmann::json(names).dump() + "\n");
      write_text_file_atomic((tmp / "made_from.json").string(), stamp.dump() + "\n");
    });
    return std::nullopt;
  } catch (const std::exception& e) {
    if (interrupted()) throw;
    spdlog::warn("frame '{}' could not be fitted: {}", frame.name, e.what());
    return std::string(e.what());
  }
}

// Every catalogue frame fitted (artifacts "fits", "views", "preview"); frames that cannot be are
// listed with the reason under "unavailable", and with the hash of the file that failed under
// "unavailable_from" (the server's own: a frame file the shop replaces is tried again, api.h). The
// job fails only when no frame fits at all (then the head, not a frame, is the likely cause: e.g. no
// face found), with the first frame's reason.
void fit_stage(const JobFolder& f, const JobSettings& s, cl::Runtime& rt, Reporter& r) {
  if (s.catalogue.empty()) return;
  const std::vector<viewer::FrameEntry> frames = viewer::catalogue_from_dir(s.catalogue);
  const std::string model_hash = fit::file_hash(f.model().string());
  nlohmann::json fits = nlohmann::json::object(), views = nlohmann::json::object();
  nlohmann::json unavailable = nlohmann::json::object(), unavailable_from = nlohmann::json::object();
  std::string first_error;
  for (size_t i = 0; i < frames.size(); ++i) {
    check_interrupt("a fit");
    const double pct = kTrainEnd + (kFitEnd - kTrainEnd) * double(i) / double(frames.size());
    r.update("fit", pct, fmt::format("placing frame {} of {} ({})", i + 1, frames.size(), frames[i].name));
    if (auto error = fit_one(f, s, rt, frames[i], model_hash)) {
      unavailable[frames[i].name] = *error;
      unavailable_from[frames[i].name] = frame_file_hash(frames[i].path);
      if (first_error.empty()) first_error = *error;
      continue;
    }
    const std::string dir = "fits/" + frame_key(frames[i].name) + "/";
    fits[frames[i].name] = dir + "placement.json";
    views[frames[i].name] = nlohmann::json::array();
    std::ifstream in(f.fit_dir(frame_key(frames[i].name)) / "views.json");
    for (const auto& n : nlohmann::json::parse(in))
      views[frames[i].name].push_back(dir + n.get<std::string>());
    if (!r.artifacts().contains("preview")) r.artifacts()["preview"] = views[frames[i].name].at(0);
  }
  if (fits.empty() && !frames.empty()) throw std::runtime_error(first_error);
  r.artifacts()["fits"] = fits;
  r.artifacts()["views"] = views;
  r.artifacts()["unavailable"] = unavailable;
  r.artifacts()["unavailable_from"] = unavailable_from;
}

// Holds job.lock in the capture folder for the worker's life (flock: released by the kernel when
// the process dies, however it dies), so two workers never run one job's stages at once; a second
// one waits, then finds the stages done and skips them.
class FolderLock {
 public:
  explicit FolderLock(const fs::path& root)
      : fd_(::open((root / "job.lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644)) {
    if (fd_ < 0 || ::flock(fd_, LOCK_EX) != 0)
      throw std::runtime_error(fmt::format("cannot lock the job folder '{}'", root.string()));
  }
  ~FolderLock() {
    if (fd_ >= 0) ::close(fd_);
  }
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  int fd_;
};

}  // namespace

JobOutcome run_job(const fs::path& folder, const cl::RuntimeOptions& runtime) {
  const JobFolder f{folder};
  std::optional<FolderLock> lock;
  try {
    lock.emplace(f.root);
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return JobOutcome::Failed;
  }
  Reporter r(f);
  try {
    const JobSettings s = read_job_settings(f.settings());
    capture_stage(f, s, r);
    cl::Runtime rt(runtime);
    train_stage(f, s, rt, r);
    fit_stage(f, s, rt, r);
    r.finish("finished", "done");
    return JobOutcome::Finished;
  } catch (const Interrupted& e) {
    r.finish("running", e.what());  // not failed: the executor hands the job back to the queue
    return JobOutcome::Interrupted;
  } catch (const std::exception& e) {
    // A stage stopped by the signal (capture, fit) ends with its own error: the job is still not
    // failed, so a server stopping its workers never fails a shopper's capture.
    if (interrupted()) {
      r.finish("running", fmt::format("stopped ({}); the job can run again", e.what()));
      return JobOutcome::Interrupted;
    }
    spdlog::error("{}", e.what());
    r.finish("failed", e.what());
    return JobOutcome::Failed;
  }
}

}  // namespace lorgnette::service
