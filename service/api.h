// The versioned JSON API of `lorgnette serve` (/api/v1, docs/service.md documents every field),
// independent of the HTTP transport (http_server.h feeds it requests and streams bodies):
//   POST   /api/v1/captures                 create a capture -> 201 {id, token, ...}
//   PUT    /api/v1/captures/{id}/video      the video (streamed to disk, size-limited, checked by bytes)
//   POST   /api/v1/captures/{id}/photos     one photo (the same checks; up to max_photos)
//   POST   /api/v1/captures/{id}/start      queue its job -> 202
//   GET    /api/v1/captures/{id}            its job: state, stage, progress, ETA, message, artifacts
//                                            (a finished job whose catalogue gained frames since is
//                                            queued again to fit them: api_refit.cpp)
//   DELETE /api/v1/captures/{id}            the capture and everything made from it -> 204
//   GET    /api/v1/queue, /metrics          admin token only (Prometheus text for /metrics)
//   GET    /api/v1/health                   no token
//   GET    /api/v1/captures/{id}/artifacts/P a finished job's preview, try-on views, placements
//   GET    /, /status.html, /tryon.html ... the shopper's pages (api_shop.cpp; no token: they carry
//                                            it in the URL fragment, which browsers never send)
// A capture's requests carry "Authorization: Bearer <token>"; an unknown id and a wrong token get
// the same 404, so a token confirms nothing about other captures.
#pragma once
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "service/executor.h"
#include "service/job_settings.h"
#include "service/job_store.h"

namespace lorgnette::service {

struct ApiRequest {
  std::string method, target, authorization;
  std::optional<uint64_t> content_length;
};

struct ApiResponse {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
};

// The shopper's page at `path` ("/" is the upload page), or nothing (api_shop.cpp).
std::optional<ApiResponse> shop_page(const std::string& path);

// The request's body, read by the transport only when the API asks for it.
class BodySource {
 public:
  virtual ~BodySource() = default;
  // Throws BodyTooLarge past `limit` bytes.
  virtual std::string read_all(uint64_t limit) = 0;
  // Streams the body into `path` (created); returns its size. Throws BodyTooLarge past `limit`,
  // InsufficientStorage when the disk fills (the caller removes the file either way).
  virtual uint64_t read_to_file(const std::filesystem::path& path, uint64_t limit) = 0;
};

struct BodyTooLarge : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// The disk (or the user's quota) filled while a body was written to a file.
struct InsufficientStorage : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ApiOptions {
  std::string data_dir;
  JobSettings job;                           // written into each new capture's job.json
  std::string admin_token_hash;              // "" = admin endpoints disabled
  uint64_t max_upload_bytes = 500ull << 20;  // per file
  int max_photos = 300;
  int64_t retention_seconds = 30 * 86400;
};

// The catalogue's frame names that `artifacts` (a job's) neither fits nor lists as unavailable with
// the file that is there now (a frame whose file the shop replaced since it failed is tried again).
std::vector<std::string> frames_not_fitted(const std::string& catalogue, const nlohmann::json& artifacts);
// The last finished progress of a job fitting new frames (api_refit.cpp).
std::filesystem::path tryon_snapshot(const std::filesystem::path& capture_dir);

class Api {
 public:
  Api(ApiOptions options, JobStore& store, Executor& executor);
  // Never throws: every failure is a response with a JSON error {"error": {"code", "message"}}.
  ApiResponse handle(const ApiRequest& request, BodySource& body);
  // Deletes captures created longer than the retention period ago; returns how many.
  int sweep_retention(int64_t now_unix);
  std::filesystem::path capture_dir(const std::string& id) const;

 private:
  ApiResponse route(const ApiRequest& request, BodySource& body);
  ApiResponse create(BodySource& body);
  ApiResponse upload(const CaptureRecord& rec, BodySource& body, std::optional<uint64_t> length, bool video);
  ApiResponse start(CaptureRecord rec);
  ApiResponse status(const CaptureRecord& rec);
  // A finished job with catalogue frames it has neither fitted nor found unavailable: queued again
  // at its fit stage, its last artifacts kept for the try-on page (api_refit.cpp). Returns the record.
  CaptureRecord fit_new_frames(CaptureRecord rec);
  ApiResponse remove(const CaptureRecord& rec);
  ApiResponse artifact(const CaptureRecord& rec, const std::string& relative);  // api_shop.cpp
  ApiResponse queue();
  ApiResponse metrics();
  CaptureRecord authorise(const std::string& id, const std::string& authorization);
  void require_admin(const std::string& authorization) const;
  void delete_capture(const std::string& id);

  ApiOptions options_;
  JobStore& store_;
  Executor& executor_;
  std::mutex upload_mutex_;  // the check-and-rename of an upload into a capture's folder
  std::mutex metrics_mutex_;
  std::map<std::string, int64_t> responses_by_status_, rejected_uploads_;
};

}  // namespace lorgnette::service
