// Staged output directories; see staged_dir.h.
#include "synth/staged_dir.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <filesystem>
#include <stdexcept>

namespace lorgnette::synth {
namespace fs = std::filesystem;

namespace {

bool non_empty_dir(const fs::path& p) { return fs::is_directory(p) && !fs::is_empty(p); }

}  // namespace

StagedDir::StagedDir(const std::string& destination, bool force) : force_(force) {
  if (destination.empty()) throw std::runtime_error("output directory: no path given (use -o DIR)");
  fs::path dest = fs::absolute(destination).lexically_normal();
  if (dest.filename().empty()) dest = dest.parent_path();
  destination_ = dest.string();
  if (fs::exists(dest) && !fs::is_directory(dest))
    throw std::runtime_error(
        fmt::format("output '{}' exists and is not a directory: choose another path", destination_));
  if (non_empty_dir(dest) && !force)
    throw std::runtime_error(
        fmt::format("output directory '{}' is not empty: choose another path or pass --force to replace it",
                    destination_));
  std::error_code ec;
  fs::create_directories(dest.parent_path(), ec);
  staging_ =
      (dest.parent_path() / fmt::format(".{}.partial-{}", dest.filename().string(), getpid())).string();
  fs::remove_all(staging_, ec);
  if (!fs::create_directory(staging_, ec) || ec)
    throw std::runtime_error(fmt::format("cannot create '{}' ({}): is the parent directory writable?",
                                         staging_, ec ? ec.message() : "unknown error"));
}

StagedDir::~StagedDir() {
  if (committed_) return;
  std::error_code ec;
  fs::remove_all(staging_, ec);
  if (ec) spdlog::warn("could not remove the staging directory '{}': {}", staging_, ec.message());
}

void StagedDir::commit() {
  std::error_code ec;
  if (fs::exists(destination_)) {
    if (non_empty_dir(destination_) && !force_)
      throw std::runtime_error(
          fmt::format("output directory '{}' appeared while writing: not replacing it", destination_));
    fs::remove_all(destination_, ec);
    if (ec) throw std::runtime_error(fmt::format("cannot replace '{}': {}", destination_, ec.message()));
  }
  fs::rename(staging_, destination_, ec);
  if (ec)
    throw std::runtime_error(
        fmt::format("cannot move the finished dataset to '{}': {}", destination_, ec.message()));
  committed_ = true;
}

}  // namespace lorgnette::synth
