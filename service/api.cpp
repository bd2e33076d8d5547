// Routing, tokens and the capture life cycle of the API (api.h); uploads are in api_upload.cpp,
// the admin endpoints in api_admin.cpp.
#include "service/api.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <nlohmann/json.hpp>
#include <vector>

#include "host/util/image_io.h"
#include "service/api_error.h"
#include "service/client_json.h"
#include "service/job_folder.h"
#include "service/progress.h"
#include "service/tokens.h"

namespace fs = std::filesystem;

namespace lorgnette::service {
namespace {

constexpr uint64_t kMaxJsonBytes = 16 * 1024;

std::vector<std::string> split_path(const std::string& target) {
  const std::string path = target.substr(0, target.find('?'));
  std::vector<std::string> parts;
  size_t i = 0;
  while (i < path.size()) {
    size_t j = path.find('/', i);
    if (j == std::string::npos) j = path.size();
    if (j > i) parts.push_back(path.substr(i, j - i));
    i = j + 1;
  }
  return parts;
}

std::string bearer(const std::string& authorization) {
  const std::string prefix = "Bearer ";
  return authorization.compare(0, prefix.size(), prefix) == 0 ? authorization.substr(prefix.size()) : "";
}

ApiResponse json_response(int status, const nlohmann::json& j) {
  return {status, "application/json", j.dump(2) + "\n"};
}

}  // namespace

Api::Api(ApiOptions options, JobStore& store, Executor& executor)
    : options_(std::move(options)), store_(store), executor_(executor) {
  fs::create_directories(fs::path(options_.data_dir) / "captures");
}

fs::path Api::capture_dir(const std::string& id) const {
  return fs::path(options_.data_dir) / "captures" / id;  // id checked by valid_capture_id first
}

ApiResponse Api::handle(const ApiRequest& request, BodySource& body) {
  ApiResponse r;
  try {
    r = route(request, body);
  } catch (const ApiError& e) {
    r = json_response(e.status, {{"error", {{"code", e.code}, {"message", e.what()}}}});
  } catch (const std::exception& e) {
    // Not one of the API's own errors: it may name a server path, which only the server's log keeps.
    spdlog::error("{} {}: {}", request.method, request.target, e.what());
    r = json_response(500, {{"error", {{"code", "internal"}, {"message", without_server_paths(e.what())}}}});
  }
  std::lock_guard<std::mutex> lock(metrics_mutex_);
  ++responses_by_status_[std::to_string(r.status)];
  return r;
}

ApiResponse Api::route(const ApiRequest& rq, BodySource& body) {
  const std::vector<std::string> p = split_path(rq.target);
  const std::string& m = rq.method;
  if (p == std::vector<std::string>{"metrics"} && m == "GET")
    return require_admin(rq.authorization), metrics();
  if (m == "GET" && (p.empty() || p[0] != "api"))
    if (auto page = shop_page(rq.target.substr(0, rq.target.find('?')))) return *page;
  if (p.size() < 3 || p[0] != "api" || p[1] != "v1")
    throw ApiError(404, "not_found", "no such endpoint: the API is under /api/v1 (docs/service.md)");
  if (p.size() == 3 && p[2] == "health" && m == "GET") return json_response(200, {{"ok", true}});
  if (p.size() == 3 && p[2] == "queue" && m == "GET") return require_admin(rq.authorization), queue();
  if (p[2] != "captures")
    throw ApiError(404, "not_found", "no such endpoint under /api/v1 (docs/service.md)");
  if (p.size() == 3) {
    if (m != "POST") throw ApiError(405, "method_not_allowed", "create a capture with POST /api/v1/captures");
    return create(body);
  }
  const bool is_artifact = p.size() > 5 && p[4] == "artifacts" && m == "GET";
  if (!valid_capture_id(p[3]) || (p.size() > 5 && !is_artifact))
    throw ApiError(404, "not_found", "no capture with this id and token");
  const CaptureRecord rec = authorise(p[3], rq.authorization);
  if (is_artifact) {
    const std::string path = rq.target.substr(0, rq.target.find('?'));
    return artifact(rec, path.substr(path.find("/artifacts/") + 11));
  }
  const std::string action = p.size() == 5 ? p[4] : "";
  if (action.empty() && m == "GET") return status(fit_new_frames(rec));
  if (action.empty() && m == "DELETE") return remove(rec);
  if (action == "video" && m == "PUT") return upload(rec, body, rq.content_length, true);
  if (action == "photos" && m == "POST") return upload(rec, body, rq.content_length, false);
  if (action == "start" && m == "POST") return start(rec);
  throw ApiError(405, "method_not_allowed",
                 fmt::format("{} is not allowed on this path (docs/service.md lists the endpoints)", m));
}

CaptureRecord Api::authorise(const std::string& id, const std::string& authorization) {
  const std::string token = bearer(authorization);
  if (token.empty())
    throw ApiError(401, "unauthorised", "send the capture's token as 'Authorization: Bearer <token>'");
  const auto rec = store_.get(id);
  // An unknown id costs the same hash and comparison as a wrong token, and gets the same answer.
  const bool ok = token_matches(token, rec ? rec->token_hash : std::string(64, '0')) && rec;
  if (!ok) throw ApiError(404, "not_found", "no capture with this id and token");
  return *rec;
}

void Api::require_admin(const std::string& authorization) const {
  if (options_.admin_token_hash.empty())
    throw ApiError(403, "admin_disabled", "admin endpoints are off: start serve with --admin-token-file");
  if (!token_matches(bearer(authorization), options_.admin_token_hash))
    throw ApiError(401, "unauthorised",
                   "this endpoint needs the admin token as 'Authorization: Bearer <token>'");
}

ApiResponse Api::create(BodySource& body) {
  std::string text;
  try {
    text = body.read_all(kMaxJsonBytes);
  } catch (const BodyTooLarge&) {
    throw ApiError(413, "too_large", fmt::format("a capture's JSON is at most {} bytes", kMaxJsonBytes));
  }
  nlohmann::json j = text.empty() ? nlohmann::json::object() : nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object())
    throw ApiError(400, "bad_json",
                   "the body must be a JSON object (or empty), e.g. {\"label\": \"order 1234\"}");
  for (const auto& [key, value] : j.items())
    if (key != "label")
      throw ApiError(400, "bad_json", fmt::format("unknown field '{}' (known: label)", key));
  if (j.contains("label") && (!j["label"].is_string() || j["label"].get<std::string>().size() > 200))
    throw ApiError(400, "bad_json", "'label' must be a string of at most 200 bytes");
  CaptureRecord r;
  r.id = new_capture_id();
  const std::string token = new_capture_token();
  r.token_hash = sha256_hex(token);
  r.created_unix = r.updated_unix = unix_now();
  const JobFolder f{capture_dir(r.id)};
  fs::create_directories(f.upload());
  write_job_settings(f.settings(), options_.job);
  if (j.contains("label")) write_text_file_atomic((f.root / "label.json").string(), j.dump() + "\n");
  store_.insert(r);
  return json_response(201, {{"id", r.id},
                             {"token", token},
                             {"state", to_string(r.state)},
                             {"created_unix", r.created_unix},
                             {"expires_unix", r.created_unix + options_.retention_seconds}});
}

ApiResponse Api::start(CaptureRecord rec) {
  std::lock_guard<std::mutex> lock(upload_mutex_);
  if (rec.state != JobState::Created)
    throw ApiError(409, "already_started",
                   fmt::format("this capture's job is already {}", to_string(rec.state)));
  if (rec.upload_kind.empty())
    throw ApiError(409, "no_upload", "upload the video (PUT .../video) or photos (POST .../photos) first");
  rec.state = JobState::Queued;
  rec.queued_unix = unix_now();
  store_.update(rec);
  ApiResponse r = status(rec);
  r.status = 202;
  return r;
}

ApiResponse Api::status(const CaptureRecord& rec) {
  nlohmann::json j = {{"id", rec.id},
                      {"state", to_string(rec.state)},
                      {"stage", rec.stage},
                      {"progress", rec.percent},
                      {"message", without_server_paths(rec.message)},
                      {"attempts", rec.attempts},
                      {"upload", rec.upload_kind},
                      {"created_unix", rec.created_unix},
                      {"updated_unix", rec.updated_unix},
                      {"expires_unix", rec.created_unix + options_.retention_seconds},
                      {"eta_seconds", nullptr},
                      {"artifacts", nlohmann::json::object()}};
  const auto p = read_progress(JobFolder{capture_dir(rec.id)}.progress());
  if (p && rec.state == JobState::Running && p->eta_seconds >= 0) j["eta_seconds"] = p->eta_seconds;
  if (p && rec.state == JobState::Finished) j["artifacts"] = client_artifacts(p->artifacts);
  // Fitting frames added since it finished: the last finished artifacts, and the frames to come.
  const auto before =
      rec.state == JobState::Finished ? std::nullopt : read_progress(tryon_snapshot(capture_dir(rec.id)));
  if (before) j["artifacts"] = client_artifacts(before->artifacts);
  return json_response(200, j);
}

void Api::delete_capture(const std::string& id) {
  executor_.cancel(id);
  std::error_code ec;
  fs::remove_all(capture_dir(id), ec);
  if (ec)
    throw std::runtime_error(fmt::format("cannot delete the folder of capture {}: {}", id, ec.message()));
  store_.remove(id);
}

ApiResponse Api::remove(const CaptureRecord& rec) {
  delete_capture(rec.id);
  return {204, "application/json", ""};
}

int Api::sweep_retention(int64_t now_unix) {
  int n = 0;
  for (const std::string& id : store_.created_before(now_unix - options_.retention_seconds)) {
    try {
      delete_capture(id);
      ++n;
    } catch (const std::exception& e) {
      spdlog::error("retention: {}", e.what());
    }
  }
  if (n) spdlog::info("retention: deleted {} capture(s) older than {} s", n, options_.retention_seconds);
  return n;
}

}  // namespace lorgnette::service
