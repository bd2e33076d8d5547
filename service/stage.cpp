// Temporary folder + rename for each stage (stage.h).
#include "service/stage.h"

#include <fmt/format.h>

#include <stdexcept>

namespace fs = std::filesystem;

namespace lorgnette::service {

fs::path partial_path(const fs::path& output) {
  return output.parent_path() / ("." + output.filename().string() + ".partial");
}

bool run_stage(const fs::path& output, const std::function<void(const fs::path&)>& work) {
  if (fs::exists(output)) return false;
  const fs::path tmp = partial_path(output);
  fs::remove_all(tmp);  // what a killed run left
  fs::create_directories(tmp);
  try {
    work(tmp);
  } catch (...) {
    std::error_code ec;
    fs::remove_all(tmp, ec);
    throw;
  }
  std::error_code ec;
  fs::rename(tmp, output, ec);
  if (ec)
    throw std::runtime_error(fmt::format("cannot move the finished stage '{}' into place as '{}': {}",
                                         tmp.string(), output.string(), ec.message()));
  return true;
}

}  // namespace lorgnette::service
