// Uploads (api.h): the body is streamed into a temporary file in the capture's upload folder with
// the size limit enforced while it arrives, then judged by its first bytes, and only then renamed
// to its final name; a refused, oversized, empty or broken upload, or one stopped by a full disk,
// leaves nothing behind.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <nlohmann/json.hpp>

#include "service/api.h"
#include "service/api_error.h"
#include "service/content_type.h"
#include "service/job_folder.h"
#include "service/tokens.h"

namespace fs = std::filesystem;

namespace lorgnette::service {
namespace {

// Removes the temporary file unless released (every early exit, including exceptions).
struct TempFile {
  fs::path path;
  ~TempFile() {
    std::error_code ec;
    if (!path.empty()) fs::remove(path, ec);
  }
};

int count_files(const fs::path& dir) {
  std::error_code ec;
  int n = 0;
  for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator(); ++it) ++n;
  return n;
}

}  // namespace

ApiResponse Api::upload(const CaptureRecord& rec, BodySource& body, std::optional<uint64_t> length,
                        bool video) {
  if (rec.state != JobState::Created)
    throw ApiError(409, "already_started",
                   "this capture's job has started: create a new capture to upload again");
  if (video ? !rec.upload_kind.empty() : rec.upload_kind == "video")
    throw ApiError(409, "upload_exists",
                   video ? "this capture already has its upload: one video, or photos, per capture"
                         : "this capture already has a video: one video, or photos, per capture");
  const JobFolder f{capture_dir(rec.id)};
  auto reject = [&](int status, const std::string& code, const std::string& message) {
    std::lock_guard<std::mutex> lock(metrics_mutex_);
    ++rejected_uploads_[code];
    return ApiError(status, code, message);
  };
  const std::string too_large =
      fmt::format("an upload is at most {} MB: film a shorter head turn or lower the resolution",
                  options_.max_upload_bytes >> 20);
  if (length && *length > options_.max_upload_bytes)
    throw reject(413, "too_large", too_large);  // before any byte
  TempFile tmp{f.upload() / (".incoming-" + random_hex(8))};
  uint64_t size = 0;
  try {
    size = body.read_to_file(tmp.path, options_.max_upload_bytes);
  } catch (const BodyTooLarge&) {
    throw reject(413, "too_large", too_large);
  } catch (const InsufficientStorage& e) {
    spdlog::error("capture {}: an upload stopped at a full disk ({}): free space under {}", rec.id, e.what(),
                  options_.data_dir);
    throw reject(507, "insufficient_storage",
                 "the server has no room for this upload right now: try again later (the operator is told)");
  }
  if (size == 0)
    throw reject(400, "empty_upload", "the upload is empty: send the video's or photo's bytes as the body");
  const Sniffed s = sniff_file(tmp.path);
  const UploadKind want = video ? UploadKind::Video : UploadKind::Image;
  if (s.kind != want)
    throw reject(415, "unsupported_content",
                 video ? "this is not a video this service reads: send an MP4, MOV, WebM, MKV or AVI file"
                       : "this is not a photo this service reads: send a JPEG or PNG file");
  std::lock_guard<std::mutex> lock(upload_mutex_);
  auto now = store_.get(rec.id);
  if (!now || now->state != JobState::Created)
    throw ApiError(409, "already_started", "this capture was started or deleted during the upload");
  fs::path final_path;
  if (video) {
    final_path = f.upload() / ("video" + s.extension);
  } else {
    fs::create_directories(f.upload() / "images");
    const int n = count_files(f.upload() / "images");
    if (n >= options_.max_photos)
      throw reject(409, "too_many_photos",
                   fmt::format("a capture holds at most {} photos", options_.max_photos));
    final_path = f.upload() / "images" / fmt::format("{:04d}{}", n, s.extension);
  }
  fs::rename(tmp.path, final_path);
  tmp.path.clear();
  CaptureRecord r = *now;
  r.upload_kind = video ? "video" : "images";
  store_.update(r);
  return {201, "application/json",
          nlohmann::json{
              {"id", r.id}, {"upload", r.upload_kind}, {"bytes", size}, {"stored_as", final_path.filename()}}
                  .dump(2) +
              "\n"};
}

}  // namespace lorgnette::service
