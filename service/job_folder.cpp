// Folder names for catalogue frames (job_folder.h).
#include "service/job_folder.h"

#include <stdexcept>

#include "fit/placement_json.h"

namespace lorgnette::service {

std::string frame_key(const std::string& frame_name) {
  std::string key;
  for (char c : frame_name) {
    const bool keep = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                      c == '.' || c == '-' || c == '_';
    key += keep ? c : '_';
  }
  if (key.empty() || key.find_first_not_of('.') == std::string::npos) key = "frame_" + key;
  return key;
}

std::string frame_file_hash(const std::string& path) {
  try {
    return fit::file_hash(path);
  } catch (const std::runtime_error&) {
    return "";
  }
}

}  // namespace lorgnette::service
