// Folder names for catalogue frames (job_folder.h).
#include "service/job_folder.h"

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

}  // namespace lorgnette::service
