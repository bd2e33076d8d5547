// The shopper's side of the API (api.h): the embedded pages and a finished job's files.
//
// Artifacts: only the files the job lists for the shopper (its "preview", "views" and "fits" in
// progress.json) are served, and only when the request names one of them exactly, so no path,
// however encoded ("..", "%2e%2e", an absolute path, a symbolic link's name), reaches anything else
// in the capture's folder or outside it: the model and the upload stay private.
#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "service/api.h"
#include "service/api_error.h"
#include "service/job_folder.h"
#include "service/progress.h"
#include "service/web_assets.h"

namespace fs = std::filesystem;

namespace lorgnette::service {
namespace {

// Every string under the artifacts the shopper may download.
void collect_paths(const nlohmann::json& j, std::vector<std::string>& out) {
  if (j.is_string()) out.push_back(j.get<std::string>());
  if (j.is_object() || j.is_array())
    for (const auto& v : j) collect_paths(v, out);
}

std::string content_type_of(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".jpg") return "image/jpeg";
  if (ext == ".png") return "image/png";
  return "application/json";
}

}  // namespace

std::optional<ApiResponse> shop_page(const std::string& path) {
  const auto& assets = web_assets();
  const auto it = assets.find(path == "/" ? "/index.html" : path);
  if (it == assets.end()) return std::nullopt;
  return ApiResponse{200, it->second.content_type, it->second.body};
}

ApiResponse Api::artifact(const CaptureRecord& rec, const std::string& relative) {
  const JobFolder f{capture_dir(rec.id)};
  // A job fitting frames added since it finished serves the files of its last finished run.
  const bool finished = rec.state == JobState::Finished;
  const auto p = read_progress(finished ? f.progress() : tryon_snapshot(f.root));
  if (!finished && !p)
    throw ApiError(
        409, "not_finished",
        fmt::format("this capture's job is {}: its files exist once it is finished", to_string(rec.state)));
  std::vector<std::string> listed;
  if (p)
    for (const char* key : {"preview", "views", "fits"})
      if (p->artifacts.contains(key)) collect_paths(p->artifacts[key], listed);
  // The worker writes these paths from sanitised frame keys (frame_key); refusing ".." and absolute
  // ones here as well keeps a damaged progress.json from leading outside the folder.
  const bool plain = !relative.empty() && relative[0] != '/' && relative.find("..") == std::string::npos;
  if (!plain || std::find(listed.begin(), listed.end(), relative) == listed.end())
    throw ApiError(404, "not_found",
                   "no such file for this capture: ask GET /api/v1/captures/{id} for its artifacts");
  std::ifstream in(f.root / relative, std::ios::binary);
  if (!in) throw ApiError(404, "not_found", "this capture's file is gone (deleted or being made again)");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return {200, content_type_of(relative), bytes.str()};
}

}  // namespace lorgnette::service
