// DeviceViews: uploads cameras, per-image pixel offsets and the concatenated RGBA pixels.
#include "host/nerf/views.h"

#include <fmt/format.h>

#include <stdexcept>

namespace lorgnette::nerf {

DeviceViews::DeviceViews(cl::Runtime& rt, const std::vector<View>& views, bool with_pixels)
    : count_(static_cast<uint32_t>(views.size())) {
  if (views.empty())
    throw std::runtime_error("no views: the dataset split is empty; check the dataset path and split");
  std::vector<uint32_t> offsets(views.size() + 1, 0);
  for (size_t i = 0; i < views.size(); ++i) {
    const Camera& c = views[i].camera;
    if (c.width == 0 || c.height == 0)
      throw std::runtime_error(fmt::format("view {} has an empty image size", i));
    if (with_pixels) {
      const Image* im = views[i].image;
      if (!im || im->channels != 4 || im->width != int(c.width) || im->height != int(c.height))
        throw std::runtime_error(
            fmt::format("view {}: the image must be {}x{} RGBA to match its camera (got {}x{}x{})", i,
                        c.width, c.height, im ? im->width : 0, im ? im->height : 0, im ? im->channels : 0));
    }
    total_pixels_ += uint64_t(c.width) * c.height;
    if (total_pixels_ >= (1ull << 32) / 4)
      throw std::runtime_error("the views hold more than 2^30 pixels: downscale the images (--downscale)");
    offsets[i + 1] = static_cast<uint32_t>(total_pixels_);
    host_cameras_.push_back(c);
  }
  cameras_ = cl::Buffer<Camera>(rt, host_cameras_);
  offsets_ = cl::Buffer<uint32_t>(rt, offsets);
  if (with_pixels) {
    try {
      pixels_ = cl::Buffer<float>(rt, total_pixels_ * 4);
    } catch (const cl::Error& e) {  // the images, not the model: say what to shrink
      throw cl::Error(fmt::format("the {} images hold {:.0f} MB as linear float RGBA, more than {} "
                                  "allocates at once: shrink them (--max-side 1024, or --downscale 2)",
                                  views.size(), total_pixels_ * 16 / 1e6, rt.device().name),
                      e.code());
    }
    for (size_t i = 0; i < views.size(); ++i)
      pixels_.write(rt, views[i].image->pixels, size_t(offsets[i]) * 4);
  } else {
    pixels_ = cl::Buffer<float>(rt, 4);
  }
  upload_kept_runs(rt, views, with_pixels);
}

void DeviceViews::upload_kept_runs(cl::Runtime& rt, const std::vector<View>& views, bool with_pixels) {
  KeptPixels kept;
  if (with_pixels) {
    std::vector<std::pair<int, int>> sizes;
    std::vector<const std::vector<IgnorePolygon>*> ignore;
    for (const View& v : views) {
      sizes.emplace_back(int(v.camera.width), int(v.camera.height));
      ignore.push_back(v.ignore);
    }
    kept = kept_pixel_runs(sizes, ignore);
  }
  sampled_pixels_ = kept.kept;
  ignored_pixels_ = kept.ignored;
  run_count_ = uint32_t(kept.runs.size() / 2);
  kept_runs_ = kept.runs.empty() ? cl::Buffer<uint32_t>(rt, 2) : cl::Buffer<uint32_t>(rt, kept.runs);
}

}  // namespace lorgnette::nerf
