// Catalogue listing, placement reading with a fallback for minimal files, nudges and safe saving
// (catalogue.h).
#include "viewer/catalogue.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>

#include "host/render/render_job.h"
#include "host/util/image_io.h"
#include "mesh/placed_glasses.h"

namespace lorgnette::viewer {
namespace fs = std::filesystem;
namespace {

bool is_frame_file(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".glb" || ext == ".gltf" || ext == ".obj" || ext == ".ply";
}

std::string timestamp() {
  std::time_t t = std::time(nullptr);
  std::tm tm{};
  localtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y%m%d-%H%M%S", &tm);
  return buf;
}

}  // namespace

std::vector<FrameEntry> catalogue_from_dir(const std::string& dir) {
  if (!fs::is_directory(dir)) throw std::runtime_error(fmt::format("catalogue '{}' is not a directory", dir));
  std::vector<FrameEntry> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_regular_file() && is_frame_file(e.path())) {
      out.push_back({e.path().filename().string(), e.path().string(), ""});
    } else if (e.is_directory()) {
      std::vector<fs::path> inside;
      for (const auto& f : fs::directory_iterator(e.path()))
        if (f.is_regular_file() && is_frame_file(f.path())) inside.push_back(f.path());
      if (inside.size() == 1) out.push_back({e.path().filename().string(), inside[0].string(), ""});
    }
  }
  std::sort(out.begin(), out.end(), [](const FrameEntry& a, const FrameEntry& b) { return a.name < b.name; });
  if (out.empty())
    throw std::runtime_error(
        fmt::format("catalogue '{}' has no frames (.glb .gltf .obj .ply, or folders holding one)", dir));
  return out;
}

std::vector<FrameEntry> catalogue_single(const std::string& frame, const std::string& placement) {
  if (!fs::is_regular_file(frame))
    throw std::runtime_error(fmt::format("glasses frame '{}' does not exist", frame));
  return {{fs::path(frame).filename().string(), frame, placement}};
}

std::optional<std::string> existing_placement(const FrameEntry& e) {
  if (!e.placement.empty()) return e.placement;
  if (fs::is_regular_file(e.save_path())) return e.save_path();
  return std::nullopt;
}

Nudge accumulate(const Nudge& n, const NudgeMsg& d) {
  if (d.reset) return {};
  Nudge o;
  o.up_mm = std::clamp(n.up_mm + d.up_mm, -kMaxNudgeMm, kMaxNudgeMm);
  o.forward_mm = std::clamp(n.forward_mm + d.forward_mm, -kMaxNudgeMm, kMaxNudgeMm);
  o.tilt_deg = std::clamp(n.tilt_deg + d.tilt_deg, -kMaxNudgeTiltDeg, kMaxNudgeTiltDeg);
  return o;
}

SaveResult save_placement(const std::string& path, const fit::PlacementFile& p, const Nudge& nudge,
                          bool overwrite) {
  SaveResult r;
  r.path = path;
  std::error_code ec;
  if (fs::exists(path, ec)) {
    if (!overwrite) {
      r.error = {"exists", fmt::format("{} exists: confirm to replace it (a backup is kept)",
                                       fs::path(path).filename().string())};
      return r;
    }
    r.backup = fmt::format("{}.{}.bak", path, timestamp());
    for (int k = 1; fs::exists(r.backup, ec); ++k)
      r.backup = fmt::format("{}.{}-{}.bak", path, timestamp(), k);
    fs::copy_file(path, r.backup, ec);
    if (ec) {
      r.error = {"io", fmt::format("cannot keep a backup of {} ({}): not saved",
                                   fs::path(path).filename().string(), ec.message())};
      r.backup.clear();
      return r;
    }
  }
  fit::PlacementFile out = p;
  out.transform = p.transform * nudge_matrix(nudge);
  // The record covers every nudge in the transform: those of earlier saves and this one.
  out.has_nudge = p.has_nudge || !nudge.zero();
  out.nudge = p.has_nudge ? fit::combined_nudge(p.nudge, nudge) : nudge;
  try {
    fit::write_placement(path, out);
  } catch (const std::exception& e) {
    r.error = {"io", fmt::format("cannot write {}: {}", fs::path(path).filename().string(), e.what())};
    return r;
  }
  r.ok = true;
  return r;
}

}  // namespace lorgnette::viewer
