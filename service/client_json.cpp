// The job's JSON as a client sees it (see client_json.h).
#include "service/client_json.h"

#include <cctype>
#include <cstring>

namespace lorgnette::service {
namespace {

bool starts_path(const std::string& t, size_t i) {
  if (t[i] != '/' || i + 1 >= t.size() || std::isspace(static_cast<unsigned char>(t[i + 1]))) return false;
  return i == 0 || std::strchr(" \t\n'\"([=", t[i - 1]) != nullptr;
}

// The end of the path starting at `i` (one past its last character).
size_t path_end(const std::string& t, size_t i) {
  const char quote = i > 0 && (t[i - 1] == '\'' || t[i - 1] == '"') ? t[i - 1] : 0;
  size_t end = i;
  if (quote) {
    end = t.find(quote, i);
    return end == std::string::npos ? t.size() : end;
  }
  while (end < t.size() && !std::isspace(static_cast<unsigned char>(t[end]))) ++end;
  while (end > i + 1 && std::strchr(":,;.)]", t[end - 1]) != nullptr) --end;
  return end;
}

// The last component of a path ("/a/b/" -> "b"); "/" stays "/".
std::string last_component(std::string p) {
  while (p.size() > 1 && p.back() == '/') p.pop_back();
  const size_t slash = p.find_last_of('/');
  return p.size() > 1 ? p.substr(slash + 1) : p;
}

}  // namespace

std::string without_server_paths(const std::string& text) {
  std::string out;
  for (size_t i = 0; i < text.size();) {
    if (!starts_path(text, i)) {
      out += text[i++];
      continue;
    }
    const size_t end = path_end(text, i);
    out += last_component(text.substr(i, end - i));
    i = end;
  }
  return out;
}

nlohmann::json client_artifacts(const nlohmann::json& artifacts) {
  nlohmann::json out = nlohmann::json::object();
  if (!artifacts.is_object()) return out;
  for (const char* key : {"preview", "views", "fits", "pending"})
    if (artifacts.contains(key)) out[key] = artifacts[key];
  if (artifacts.contains("unavailable") && artifacts["unavailable"].is_object()) {
    out["unavailable"] = nlohmann::json::object();
    for (const auto& [frame, why] : artifacts["unavailable"].items())
      out["unavailable"][frame] = why.is_string() ? without_server_paths(why.get<std::string>()) : "";
  }
  return out;
}

}  // namespace lorgnette::service
