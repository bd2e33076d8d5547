// Frames added to the shop's catalogue after a capture's job finished (api.h): the try-on page
// asks for the job, finds frames that are neither fitted nor known to be unavailable, and the job
// goes back to the queue at its fit stage. Its worker skips the capture and training (their
// outputs are there), reuses every cached fit (made_from.json: the same model and frame file
// hashes) and fits only the new frames. Meanwhile the try-on page keeps the frames it had: the
// last finished progress is kept as tryon.json and serves the artifacts until the job finishes again.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "host/util/image_io.h"
#include "service/api.h"
#include "service/job_folder.h"
#include "service/job_settings.h"
#include "service/progress.h"
#include "viewer/catalogue.h"

namespace fs = std::filesystem;

namespace lorgnette::service {
namespace {

bool lists(const nlohmann::json& artifacts, const char* key, const std::string& frame) {
  return artifacts.contains(key) && artifacts[key].is_object() && artifacts[key].contains(frame);
}

// Whether the frame failed with the file that is in the catalogue now. A job that recorded no hash
// for it (made before the hashes were kept) counts it as the same file.
bool failed_with_this_file(const nlohmann::json& artifacts, const viewer::FrameEntry& frame) {
  if (!lists(artifacts, "unavailable", frame.name)) return false;
  if (!lists(artifacts, "unavailable_from", frame.name)) return true;
  const nlohmann::json& was = artifacts["unavailable_from"][frame.name];
  return !was.is_string() || was.get<std::string>() == frame_file_hash(frame.path);
}

}  // namespace

std::vector<std::string> frames_not_fitted(const std::string& catalogue, const nlohmann::json& artifacts) {
  std::vector<std::string> out;
  if (catalogue.empty()) return out;
  std::vector<viewer::FrameEntry> frames;
  try {
    frames = viewer::catalogue_from_dir(catalogue);
  } catch (const std::exception&) {
    return out;  // no frames there now (emptied, or the folder is gone): nothing to add
  }
  for (const auto& f : frames)
    if (!lists(artifacts, "fits", f.name) && !failed_with_this_file(artifacts, f)) out.push_back(f.name);
  return out;
}

fs::path tryon_snapshot(const fs::path& capture_dir) { return capture_dir / "tryon.json"; }

CaptureRecord Api::fit_new_frames(CaptureRecord rec) {
  // A server without a catalogue has none to add (and a status request stays one store read).
  if (rec.state != JobState::Finished || options_.job.catalogue.empty()) return rec;
  const JobFolder f{capture_dir(rec.id)};
  const auto p = read_progress(f.progress());
  if (!p) return rec;
  std::string catalogue;
  try {
    catalogue = read_job_settings(f.settings()).catalogue;
  } catch (const std::exception& e) {
    spdlog::warn("job {}: cannot read its settings to look for new frames: {}", rec.id, e.what());
    return rec;
  }
  const std::vector<std::string> added = frames_not_fitted(catalogue, p->artifacts);
  if (added.empty()) return rec;
  Progress snapshot = *p;
  snapshot.artifacts["pending"] = added;  // shown as being fitted until the job finishes again
  write_text_file_atomic(tryon_snapshot(f.root).string(), snapshot.to_json().dump(2) + "\n");
  std::string names;
  for (const auto& n : added) names += (names.empty() ? "" : ", ") + n;
  rec.state = JobState::Queued;
  rec.stage = "fit";
  rec.percent = 80.0;
  rec.message = fmt::format("fitting {} frame(s) added to the shop's catalogue: {}", added.size(), names);
  rec.queued_unix = unix_now();
  // Two servers doing this at once both queue the job; it is claimed once.
  store_.update(rec);
  spdlog::info("job {}: {}", rec.id, rec.message);
  return rec;
}

}  // namespace lorgnette::service
