// The dataset loader: finds the json file(s), assigns splits, validates, then reads and downscales the
// images and builds the Cameras. Conventions are documented in dataset.h.
#include "host/dataset/dataset.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <stdexcept>

#include "host/dataset/frame_image.h"
#include "host/dataset/transforms_parse.h"
#include "host/util/name_list.h"

namespace lorgnette::dataset {
namespace fs = std::filesystem;
using detail::FrameSpec;
using nlohmann::json;

const char* to_string(Split split) {
  switch (split) {
    case Split::Train:
      return "train";
    case Split::Val:
      return "val";
    case Split::Test:
      return "test";
    case Split::Holdout:
      return "holdout";
  }
  return "?";
}

Split split_from_string(const std::string& name) {
  for (Split s : {Split::Train, Split::Val, Split::Test, Split::Holdout})
    if (name == to_string(s)) return s;
  throw std::runtime_error(fmt::format("unknown split '{}': use train, val, test or holdout", name));
}

std::vector<const Frame*> Dataset::split(Split s) const {
  std::vector<const Frame*> out;
  for (const Frame& f : frames)
    if (f.split == s) out.push_back(&f);
  return out;
}

bool Dataset::has_split(Split s) const {
  return std::any_of(frames.begin(), frames.end(), [s](const Frame& f) { return f.split == s; });
}

Split Dataset::default_eval_split() const {
  return format == "nerf-synthetic" ? Split::Test : Split::Holdout;
}

std::vector<const Frame*> Dataset::require_split(Split s) const {
  auto out = split(s);
  if (out.empty()) {
    std::string have;
    for (Split t : {Split::Train, Split::Val, Split::Test, Split::Holdout})
      if (has_split(t)) have += std::string(have.empty() ? "" : ", ") + to_string(t);
    throw std::runtime_error(
        fmt::format("dataset '{}' has no '{}' frames (it has: {}); {}", root, to_string(s),
                    have.empty() ? "none loaded" : have,
                    format == "nerf-synthetic" ? "use --split test or val" : "use --split holdout"));
  }
  return out;
}

std::pair<Eigen::Vector3f, Eigen::Vector3f> Dataset::camera_bounds() const {
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(INFINITY), hi = -lo;
  for (const Frame& f : frames) {
    Eigen::Vector3f o(f.camera.c2w[3], f.camera.c2w[7], f.camera.c2w[11]);
    lo = lo.cwiseMin(o);
    hi = hi.cwiseMax(o);
  }
  return {lo, hi};
}

Eigen::Matrix4d camera_to_matrix(const Camera& cam) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = cam.c2w[r * 4 + c];
  return m;
}

void set_camera_pose(Camera& cam, const Eigen::Matrix4d& c2w) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) cam.c2w[r * 4 + c] = static_cast<float>(c2w(r, c));
}

namespace {

struct Source {
  std::string root, format;
  std::vector<std::pair<std::string, Split>> files;  // json files and the split they hold
};

Source find_source(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec))
    throw std::runtime_error(
        fmt::format("dataset '{}' does not exist: give a directory holding transforms.json "
                    "(or transforms_train/val/test.json), or the json file itself",
                    path));
  Source s;
  fs::path dir = fs::is_directory(path, ec) ? fs::path(path) : fs::path(path).parent_path();
  s.root = fs::absolute(dir).lexically_normal().string();
  std::string name = fs::path(path).filename().string();
  bool synthetic_file = !fs::is_directory(path, ec) && name.rfind("transforms_", 0) == 0;
  if (!fs::is_directory(path, ec) && !synthetic_file) {
    s.format = "transforms";
    s.files.emplace_back(fs::absolute(path).string(), Split::Train);
    return s;
  }
  if (!synthetic_file && fs::exists(dir / "transforms.json", ec)) {
    s.format = "transforms";
    s.files.emplace_back((dir / "transforms.json").string(), Split::Train);
    return s;
  }
  for (Split sp : {Split::Train, Split::Val, Split::Test}) {
    fs::path f = dir / fmt::format("transforms_{}.json", to_string(sp));
    if (fs::exists(f, ec)) s.files.emplace_back(f.string(), sp);
  }
  if (s.files.empty())
    throw std::runtime_error(
        fmt::format("no transforms.json or transforms_{{train,val,test}}.json in '{}': is this "
                    "a NeRF dataset directory?",
                    s.root));
  s.format = "nerf-synthetic";
  return s;
}

bool wanted(const LoadOptions& o, Split s) {
  return o.splits.empty() || std::find(o.splits.begin(), o.splits.end(), s) != o.splits.end();
}

// Parses every json, assigns holdout for single-file datasets, validates poses over all frames.
// `listed`: the names (file stems) of every frame the parsed json files list.
std::vector<FrameSpec> collect_frames(const Source& src, Dataset& ds, const LoadOptions& opt,
                                      std::set<std::string>& listed) {
  std::vector<FrameSpec> all;
  for (const auto& [file, split] : src.files) {
    if (src.format == "nerf-synthetic" && !wanted(opt, split)) continue;
    json doc = detail::read_json_file(file);
    auto frames = detail::parse_frames(doc, file, split);
    detail::check_masks_all_or_none(frames, file);
    if (src.format == "transforms") {
      std::stable_sort(frames.begin(), frames.end(),
                       [](const FrameSpec& a, const FrameSpec& b) { return a.file_path < b.file_path; });
      for (size_t i = 0; i < frames.size(); ++i) frames[i].split = i % 8 == 0 ? Split::Holdout : Split::Train;
    }
    if (all.empty()) {  // dataset-level metadata from the first file
      if (auto it = doc.find("aabb_scale"); it != doc.end() && it->is_number())
        ds.aabb_scale = it->get<float>();
      if (auto it = doc.find("scale"); it != doc.end() && it->is_number()) ds.scale = it->get<float>();
      if (auto it = doc.find("offset"); it != doc.end() && it->is_array() && it->size() == 3)
        ds.offset = std::array<float, 3>{(*it)[0].get<float>(), (*it)[1].get<float>(), (*it)[2].get<float>()};
      if (auto it = doc.find("aabb"); it != doc.end()) ds.aabb = detail::parse_aabb(*it, file);
      if (auto it = doc.find("applied_transform"); it != doc.end()) {
        ds.applied_transform = detail::parse_pose(*it, file + ": applied_transform");
        ds.has_applied_transform = true;
      }
    }
    for (const auto& f : frames) listed.insert(fs::path(f.file_path).stem().string());
    all.insert(all.end(), frames.begin(), frames.end());
  }
  detail::check_not_degenerate(all);
  std::vector<FrameSpec> kept;
  std::vector<std::string> missing;
  size_t wanted_frames = 0;
  for (auto& f : all) {
    if (!wanted(opt, f.split)) continue;
    ++wanted_frames;
    if (f.image_path.empty()) {
      missing.push_back(f.file_path);
      continue;
    }
    kept.push_back(std::move(f));
  }
  if (missing.empty()) return kept;
  std::string json_files;
  for (const auto& [file, split] : src.files)
    json_files += (json_files.empty() ? "" : ", ") + fs::path(file).filename().string();
  std::string names = name_list(missing), frames;  // "frames", or "train frames" for chosen splits
  for (Split sp : opt.splits) frames += (frames.empty() ? "" : "/") + std::string(to_string(sp));
  frames += frames.empty() ? "frames" : " frames";
  const bool too_few = kept.size() < kMinFramesLeft || 2 * kept.size() < wanted_frames;
  if (too_few && !opt.any_missing_images_ok)
    throw std::runtime_error(fmt::format(
        "dataset '{}': {} of {} {} name an image file that is not there ({}), so only {} would remain (at "
        "least {} and at least half are needed): restore those images, remove their frames from {}, or "
        "re-run `lorgnette capture` to make the dataset again",
        src.root, missing.size(), wanted_frames, frames, names, kept.size(), kMinFramesLeft, json_files));
  spdlog::warn("dataset '{}': skipping {} of {} {} whose image file is missing ({}); {} remain", src.root,
               missing.size(), wanted_frames, frames, names, kept.size());
  return kept;
}

// Keeps at most max_frames per split, evenly spaced over the split's frames.
std::vector<FrameSpec> limit_frames(std::vector<FrameSpec> frames, int max_frames) {
  if (max_frames <= 0) return frames;
  std::vector<bool> keep(frames.size(), false);
  for (Split s : {Split::Train, Split::Val, Split::Test, Split::Holdout}) {
    std::vector<size_t> of;
    for (size_t i = 0; i < frames.size(); ++i)
      if (frames[i].split == s) of.push_back(i);
    size_t n = std::min(of.size(), static_cast<size_t>(max_frames));
    for (size_t i = 0; i < n; ++i) keep[of[i * of.size() / n]] = true;
  }
  std::vector<FrameSpec> out;  // dataset order is kept
  for (size_t i = 0; i < frames.size(); ++i)
    if (keep[i]) out.push_back(std::move(frames[i]));
  return out;
}

// nerfstudio's per-frame mask (0 = background) as the image's alpha: alpha *= mask. Checked to
// exist and to match the image's size; `image` null checks only (cameras-only loads).
void apply_mask(const FrameSpec& spec, Image* image, int w, int h) {
  if (spec.mask_path.empty())
    throw std::runtime_error(
        fmt::format("{}: its mask_path '{}' names a file that is not there: restore the mask, fix "
                    "'mask_path', or remove 'mask_path' from every frame (train then separates the "
                    "subject from the room itself)",
                    spec.where, spec.mask_file_path));
  int mw, mh;
  Image mask;
  try {
    if (image) {
      mask = detail::read_mask(spec.mask_path);
      mw = mask.width, mh = mask.height;
    } else {
      auto hdr = detail::read_image_header(spec.mask_path);
      mw = hdr.width, mh = hdr.height;
    }
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(
        fmt::format("{}: {}; replace the mask or remove 'mask_path' from every frame", spec.where, e.what()));
  }
  if (mw != w || mh != h)
    throw std::runtime_error(
        fmt::format("{}: mask '{}' is {}x{} but its image '{}' is {}x{}: write each mask at its image's "
                    "size (one value per pixel, 0 = background)",
                    spec.where, spec.mask_path, mw, mh, spec.image_path, w, h));
  if (!image) return;
  for (size_t p = 0; p < mask.pixels.size(); ++p) image->pixels[p * 4 + 3] *= mask.pixels[p];
}

Frame load_frame(const FrameSpec& spec, const LoadOptions& opt, bool* has_alpha) {
  Frame f;
  f.name = fs::path(spec.image_path).stem().string();
  f.image_path = spec.image_path;
  f.split = spec.split;
  int w, h;
  try {
    if (opt.load_images) {
      bool alpha = false;
      f.image = detail::read_rgba(spec.image_path, &alpha);
      *has_alpha = *has_alpha || alpha;
      w = f.image.width;
      h = f.image.height;
    } else {
      auto hdr = detail::read_image_header(spec.image_path);
      *has_alpha = *has_alpha || hdr.has_alpha;
      w = hdr.width;
      h = hdr.height;
    }
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(
        fmt::format("{}: {}; replace the file or remove the frame from the json", spec.where, e.what()));
  }
  f.camera = detail::make_camera(spec, w, h);
  if (!spec.mask_file_path.empty()) {
    apply_mask(spec, opt.load_images ? &f.image : nullptr, w, h);
    *has_alpha = true;
  }
  int nw, nh;
  detail::scaled_size(w, h, opt.downscale, opt.max_side, &nw, &nh);
  if (nw != w || nh != h) {
    float sx = static_cast<float>(nw) / w, sy = static_cast<float>(nh) / h;
    f.camera.fx *= sx;
    f.camera.cx *= sx;
    f.camera.fy *= sy;
    f.camera.cy *= sy;
    f.camera.width = static_cast<lgn_uint>(nw);
    f.camera.height = static_cast<lgn_uint>(nh);
    if (opt.load_images) f.image = detail::resize_rgba(f.image, nw, nh);
  }
  return f;
}

void read_ground_truth(Dataset& ds) {
  fs::path gt = fs::path(ds.root) / "ground_truth.json";
  std::error_code ec;
  if (!fs::exists(gt, ec)) return;
  ds.ground_truth = detail::read_json_file(gt.string());
  if (auto it = ds.ground_truth.find("mm_per_unit"); it != ds.ground_truth.end() && !it->is_null()) {
    if (!it->is_number() || !(it->get<double>() > 0) || !std::isfinite(it->get<double>()))
      throw std::runtime_error(
          fmt::format("'{}': mm_per_unit must be a positive number, found {}", gt.string(), it->dump()));
    ds.mm_per_unit = it->get<double>();
  }
}

// `opt` with max_side lowered so that the frames' images, as loaded, hold at most
// opt.max_image_bytes (their headers read for their sizes); `opt` itself when they fit already.
LoadOptions within_image_budget(const std::vector<FrameSpec>& specs, const LoadOptions& opt) {
  if (!opt.load_images || opt.max_image_bytes == 0) return opt;
  std::vector<std::pair<int, int>> sizes;
  for (const FrameSpec& spec : specs) {
    if (spec.image_path.empty()) continue;  // a missing image: load_frame says so
    try {
      const detail::ImageHeader hdr = detail::read_image_header(spec.image_path);
      sizes.emplace_back(hdr.width, hdr.height);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(
          fmt::format("{}: {}; replace the file or remove the frame from the json", spec.where, e.what()));
    }
  }
  int longest = 0;
  auto bytes_at = [&](int max_side) {
    uint64_t bytes = 0;
    longest = 0;
    for (const auto& [w, h] : sizes) {
      int nw, nh;
      detail::scaled_size(w, h, opt.downscale, max_side, &nw, &nh);
      bytes += uint64_t(nw) * uint64_t(nh) * 4u * sizeof(float);
      longest = std::max({longest, nw, nh});
    }
    return bytes;
  };
  const uint64_t full = bytes_at(opt.max_side);
  if (full <= opt.max_image_bytes) return opt;
  const int full_longest = longest;
  LoadOptions shrunk = opt;
  uint64_t bytes = full;
  // Lowering max_side by a factor s shrinks every image by s or less (the largest most), so repeat
  // until the sum fits; each round lowers it, and 16 px is the floor.
  while (bytes > opt.max_image_bytes && shrunk.max_side != 16) {
    const double s = std::sqrt(double(opt.max_image_bytes) / double(bytes)) * 0.995;
    shrunk.max_side = std::max(16, std::min(longest - 1, int(std::floor(longest * s))));
    bytes = bytes_at(shrunk.max_side);
  }
  spdlog::warn(
      "the {} images would hold {:.1f} GB in memory, up to {} px on the longer side (linear float "
      "RGBA): shrinking them to at most {} px ({:.2f} GB; the budget is {:.2f} GB). Give --max-side or "
      "--downscale to choose the size yourself",
      sizes.size(), full / 1e9, full_longest, shrunk.max_side, bytes / 1e9, opt.max_image_bytes / 1e9);
  return shrunk;
}

// The ignore regions of the loaded frames (ignore_regions.h), scaled to their loaded size. `listed`:
// the names of every frame of the json files read; `whole`: those were all of the dataset's files,
// so a name outside them means the file belongs to another dataset.
void attach_ignore_regions(Dataset& ds, const std::set<std::string>& listed, bool whole) {
  const std::optional<IgnoreRegions> regions = read_ignore_regions(ds.root);
  if (!regions) return;
  const std::string file = (fs::path(ds.root) / kIgnoreRegionsFile).string();
  size_t frames = 0;
  for (const FrameIgnore& fi : regions->frames) {
    if (whole && !listed.count(fi.name))
      throw std::runtime_error(fmt::format(
          "'{}' names frame '{}', which the dataset does not list: it belongs to another capture; run "
          "`lorgnette capture --card-only {}` again or delete it",
          file, fi.name, ds.root));
    for (Frame& f : ds.frames) {
      if (f.name != fi.name) continue;
      const double aspect = double(fi.width) / fi.height, loaded = double(f.camera.width) / f.camera.height;
      if (std::abs(aspect / loaded - 1.0) > 0.01)
        throw std::runtime_error(fmt::format(
            "'{}': frame '{}' has regions drawn on a {}x{} image but its image is {}x{} (another shape): "
            "run `lorgnette capture --card-only {}` again or delete the file",
            file, fi.name, fi.width, fi.height, f.camera.width, f.camera.height, ds.root));
      f.ignore = scale_polygons(fi.polygons, fi.width, fi.height, int(f.camera.width), int(f.camera.height));
      frames += f.ignore.empty() ? 0 : 1;
    }
  }
  spdlog::info("dataset: ignore regions ({}) in {} of {} loaded frames", regions->source, frames,
               ds.frames.size());
}

}  // namespace

Dataset load_dataset(const std::string& path, const LoadOptions& options) {
  if (options.downscale < 1 || options.max_side < 0 || options.max_frames < 0)
    throw std::runtime_error(
        fmt::format("invalid load options: downscale {} (must be >= 1), max_side {}, "
                    "max_frames {} (must be >= 0)",
                    options.downscale, options.max_side, options.max_frames));
  Source src = find_source(path);
  Dataset ds;
  ds.root = src.root;
  ds.format = src.format;
  std::set<std::string> listed;
  auto specs = limit_frames(collect_frames(src, ds, options, listed), options.max_frames);
  if (specs.empty())
    throw std::runtime_error(
        fmt::format("dataset '{}' has no frames to load for the requested splits", ds.root));
  const LoadOptions sized = within_image_budget(specs, options);
  ds.frames.reserve(specs.size());
  for (const auto& spec : specs) ds.frames.push_back(load_frame(spec, sized, &ds.has_alpha));
  read_ground_truth(ds);
  attach_ignore_regions(ds, listed, src.format == "transforms" || options.splits.empty());
  size_t bytes = 0;
  for (const Frame& f : ds.frames) bytes += f.image.pixels.size() * sizeof(float);
  spdlog::info("dataset '{}' ({}): {} frames, {}x{}{}, {:.0f} MB of images", ds.root, ds.format,
               ds.frames.size(), ds.frames[0].camera.width, ds.frames[0].camera.height,
               ds.has_alpha ? ", RGBA" : "", bytes / 1e6);
  return ds;
}

}  // namespace lorgnette::dataset
