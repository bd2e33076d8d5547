// Matte files; see matte.h. image_io encodes 8-bit files as sRGB, so the coverage is passed
// through the inverse transfer on the way out and the forward one on the way in: the stored byte
// is round(255 * coverage).
#include "synth/matte.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace lorgnette::synth {

void write_matte(const std::string& path, const Image& matte) {
  if (matte.channels != 1) throw std::runtime_error("write_matte: the matte must have one channel");
  Image out(matte.width, matte.height, 1);
  for (size_t i = 0; i < matte.pixels.size(); ++i)
    out.pixels[i] = srgb_to_linear(std::round(std::clamp(matte.pixels[i], 0.0f, 1.0f) * 255.0f) / 255.0f);
  write_image(path, out);
}

Image read_matte(const std::string& path) {
  Image in = read_image(path);
  Image out(in.width, in.height, 1);
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x)
      out.at(x, y, 0) = std::clamp(linear_to_srgb(in.at(x, y, 0)), 0.0f, 1.0f);
  return out;
}

std::map<std::string, EvalFiles> eval_files_by_stem(const std::string& dataset_dir) {
  namespace fs = std::filesystem;
  std::map<std::string, EvalFiles> by_stem;
  std::ifstream in(fs::path(dataset_dir) / "transforms.json");
  if (!in) return by_stem;
  const nlohmann::json tj = nlohmann::json::parse(in, nullptr, false);
  if (tj.is_discarded() || !tj.contains("frames") || !tj["frames"].is_array()) return by_stem;
  for (const auto& f : tj["frames"])
    if (f.is_object() && f.contains("eval_matte_path") && f["eval_matte_path"].is_string())
      by_stem[fs::path(f.value("file_path", "")).stem().string()] = {f["eval_matte_path"].get<std::string>(),
                                                                     f.value("depth_path", "")};
  return by_stem;
}

}  // namespace lorgnette::synth
