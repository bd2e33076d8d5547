// The output-folder rule and staged outputs; see output_folder.h.
#include "host/util/output_folder.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "host/util/file_write.h"

namespace lorgnette {
namespace fs = std::filesystem;
namespace {

fs::path absolute_path(const fs::path& p) {
  fs::path a = fs::weakly_canonical(fs::absolute(p)).lexically_normal();
  if (a.filename().empty() && a.has_parent_path() && a != a.root_path()) a = a.parent_path();
  return a;
}

// True when `inner` is `outer` or lies inside it (both absolute and normal).
bool within(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i)
    if (i == inner.end() || *i != *o) return false;
  return true;
}

std::string read_marker_command(const fs::path& dir) {
  std::ifstream in(dir / kOutputMarker);
  if (!in) return "";
  nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  return j.is_object() && j.value("command", nlohmann::json()).is_string() ? j["command"].get<std::string>()
                                                                           : "";
}

void refuse_inputs_inside(const fs::path& dir, const OutputOwner& owner,
                          const std::vector<std::string>& inputs) {
  for (const std::string& input : inputs) {
    if (input.empty()) continue;
    if (within(absolute_path(input), dir))
      throw std::runtime_error(fmt::format(
          "the input '{}' lies inside the output folder '{}', which {} would replace: move the input out "
          "of it or choose another output folder (nothing was changed)",
          input, dir.string(), owner.command));
  }
}

}  // namespace

bool is_output_of(const fs::path& dir, const OutputOwner& owner) {
  std::error_code ec;
  if (read_marker_command(dir) == owner.command) return true;
  return !owner.legacy_marker.empty() && fs::is_regular_file(dir / owner.legacy_marker, ec);
}

void mark_output(const fs::path& dir, const OutputOwner& owner) {
  nlohmann::json j = {{"command", owner.command},
                      {"note", "made by `lorgnette " + owner.command + "`; --force may replace this folder"}};
  write_file_atomic((dir / kOutputMarker).string(), j.dump(2) + "\n");
}

bool check_output_folder(const fs::path& requested, const OutputOwner& owner, bool force,
                         const std::vector<std::string>& inputs) {
  if (requested.empty()) throw std::runtime_error("no output folder given (use -o DIR)");
  const fs::path dir = absolute_path(requested);
  std::error_code ec;
  if (within(absolute_path(fs::current_path(ec)), dir))
    throw std::runtime_error(fmt::format(
        "the output folder '{}' is the working directory or a folder above it, which {} would replace: "
        "choose a new folder such as -o {}-output (nothing was changed)",
        requested.string(), owner.command, owner.command));
  refuse_inputs_inside(dir, owner, inputs);
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw std::runtime_error(
        fmt::format("output '{}' exists and is not a folder: choose another path", requested.string()));
  if (!fs::exists(dir, ec) || fs::is_empty(dir, ec)) return false;
  if (!is_output_of(dir, owner))
    throw std::runtime_error(fmt::format(
        "output folder '{}' is not empty and is not an earlier {} (--force replaces only those): choose a "
        "new folder (nothing was changed)",
        requested.string(), owner.noun));
  if (!force)
    throw std::runtime_error(fmt::format(
        "'{}' holds an earlier {}: pass --force to replace it or choose a new folder (nothing was changed)",
        requested.string(), owner.noun));
  return true;
}

StagedOutput::StagedOutput(const std::string& destination, OutputOwner owner, bool force,
                           const std::vector<std::string>& inputs)
    : owner_(std::move(owner)), force_(force) {
  replaces_ = check_output_folder(destination, owner_, force, inputs);
  const fs::path dest = absolute_path(destination);
  destination_ = dest.string();
  std::error_code ec;
  fs::create_directories(dest.parent_path(), ec);
  staging_ =
      (dest.parent_path() / fmt::format(".{}.partial-{}", dest.filename().string(), getpid())).string();
  fs::remove_all(staging_, ec);
  if (!fs::create_directory(staging_, ec) || ec)
    throw std::runtime_error(fmt::format("cannot create '{}' ({}): is the parent folder writable?", staging_,
                                         ec ? ec.message() : "unknown error"));
}

StagedOutput::~StagedOutput() {
  if (committed_) return;
  std::error_code ec;
  fs::remove_all(staging_, ec);
  if (ec) spdlog::warn("could not remove the staging folder '{}': {}", staging_, ec.message());
}

void StagedOutput::commit() {
  // The destination may have changed while the work ran: the rule is checked again.
  check_output_folder(destination_, owner_, force_);
  mark_output(staging_, owner_);
  std::error_code ec;
  const fs::path dest(destination_);
  const std::string old =
      (dest.parent_path() / fmt::format(".{}.old-{}", dest.filename().string(), getpid())).string();
  const bool had_old = fs::exists(destination_, ec);
  if (had_old) {
    fs::rename(destination_, old, ec);
    if (ec) throw std::runtime_error(fmt::format("cannot move '{}' aside: {}", destination_, ec.message()));
  }
  fs::rename(staging_, destination_, ec);
  if (ec) {
    std::error_code back;
    if (had_old) fs::rename(old, destination_, back);
    throw std::runtime_error(fmt::format("cannot move the finished output to '{}': {}{}", destination_,
                                         ec.message(),
                                         had_old && !back ? " (the earlier one is unchanged)" : ""));
  }
  committed_ = true;
  if (had_old) fs::remove_all(old, ec);
  if (ec) spdlog::warn("could not remove the replaced output '{}': {}", old, ec.message());
}

void refuse_output_onto_input(const std::string& output, const std::vector<std::string>& inputs,
                              const std::string& option) {
  if (output.empty()) return;
  std::error_code ec;
  const fs::path out = fs::weakly_canonical(fs::absolute(output, ec), ec);
  for (const auto& in : inputs) {
    if (in.empty()) continue;
    std::error_code e1, e2;
    const bool same = fs::equivalent(output, in, e1) ||
                      (!ec && fs::weakly_canonical(fs::absolute(in, e2), e2) == out && !e2);
    if (same)
      throw std::runtime_error(fmt::format(
          "{} '{}' is the input '{}': writing the output there would destroy it (--force does not "
          "allow that); choose another {}",
          option, output, in, option));
  }
}

fs::path nearest_existing_folder(const fs::path& path) {
  std::error_code ec;
  fs::path p = path.lexically_normal();
  while (!p.empty() && !fs::exists(fs::symlink_status(p, ec))) p = p.parent_path();
  return p.empty() ? fs::path(".") : p;
}

NewOutputs::NewOutputs(const fs::path& dir, const std::vector<std::string>& names) : names_(names) {
  std::error_code ec;
  fs::path p = fs::absolute(dir).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();
  dir_ = p;
  if (!fs::exists(fs::symlink_status(p, ec))) {
    while (p.has_parent_path() && p.parent_path() != p &&
           !fs::exists(fs::symlink_status(p.parent_path(), ec)))
      p = p.parent_path();
    created_ = p;
    fs::create_directories(dir);
    return;
  }
  for (const auto& n : names)
    if (fs::exists(fs::symlink_status(dir_ / n, ec))) moved_.push_back(n);
  if (moved_.empty()) return;
  aside_ = dir_ / fmt::format(".lorgnette-replaced-{}", getpid());
  std::vector<std::string> to_move;
  to_move.swap(moved_);
  try {
    fs::create_directory(aside_);
    for (const auto& n : to_move) fs::rename(dir_ / n, aside_ / n), moved_.push_back(n);
  } catch (...) {
    put_back();
    throw;
  }
}

void NewOutputs::put_back() {
  std::error_code ec;
  for (const auto& n : moved_)
    if (!fs::exists(fs::symlink_status(dir_ / n, ec))) {
      fs::rename(aside_ / n, dir_ / n, ec);
      if (ec) spdlog::warn("could not put '{}' back from '{}': {}", n, aside_.string(), ec.message());
    }
  if (aside_.empty()) return;
  if (keep_)
    fs::remove_all(aside_, ec);
  else
    fs::remove(aside_, ec);  // only when empty: a file that could not go back stays in it
  if (ec) spdlog::warn("could not remove '{}': {}", aside_.string(), ec.message());
}

NewOutputs::~NewOutputs() {
  std::error_code ec;
  if (!keep_ && !created_.empty()) {
    fs::remove_all(created_, ec);
    if (ec) spdlog::warn("could not remove the unfinished output '{}': {}", created_.string(), ec.message());
    return;
  }
  if (!keep_)
    for (const auto& n : names_) {
      fs::remove(dir_ / n, ec);
      if (ec)
        spdlog::warn("could not remove the unfinished output '{}': {}", (dir_ / n).string(), ec.message());
    }
  put_back();
}

}  // namespace lorgnette
