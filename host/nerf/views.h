// Training/evaluation views on the device: the cameras, the pixel offset of each image inside one
// concatenated pixel array, and the pixels themselves (linear straight-alpha RGBA, 4 floats each).
// The sampler picks training pixels uniformly over all of them but those in the views' ignore
// regions (host/nerf/kept_pixels.h).
#pragma once
#include <cstdint>
#include <vector>

#include "common/camera_types.h"
#include "host/cl/buffer.h"
#include "host/nerf/kept_pixels.h"
#include "host/util/image_io.h"

namespace lorgnette::nerf {

// One posed image; `image` may be null for render-only views (4 channels: linear RGBA).
struct View {
  Camera camera{};
  const Image* image = nullptr;
  // Regions of this view training leaves out (a held card and its fingers): never sampled. Null or
  // empty: every pixel is trained on.
  const std::vector<IgnorePolygon>* ignore = nullptr;
};

class DeviceViews {
 public:
  // with_pixels: upload the images (every view must have one of its camera's size) and, when a view
  // has ignore regions, the table of kept pixels.
  DeviceViews(cl::Runtime& rt, const std::vector<View>& views, bool with_pixels);

  uint32_t count() const { return count_; }
  uint64_t total_pixels() const { return total_pixels_; }
  const std::vector<Camera>& cameras() const { return host_cameras_; }
  const cl::Buffer<Camera>& camera_buffer() const { return cameras_; }
  const cl::Buffer<uint32_t>& offsets() const { return offsets_; }
  const cl::Buffer<float>& pixels() const { return pixels_; }
  // The training sampler's pixels: all, or the kept ones when some are ignored (then kept_runs()
  // holds run_count() pairs mapping a kept index to its global pixel; kept_pixels.h).
  uint64_t sampled_pixels() const { return ignored_pixels_ ? sampled_pixels_ : total_pixels_; }
  uint64_t ignored_pixels() const { return ignored_pixels_; }
  uint32_t run_count() const { return run_count_; }
  const cl::Buffer<uint32_t>& kept_runs() const { return kept_runs_; }

 private:
  void upload_kept_runs(cl::Runtime& rt, const std::vector<View>& views, bool with_pixels);

  uint32_t count_ = 0;
  uint64_t total_pixels_ = 0, sampled_pixels_ = 0, ignored_pixels_ = 0;
  uint32_t run_count_ = 0;
  std::vector<Camera> host_cameras_;
  cl::Buffer<Camera> cameras_;
  cl::Buffer<uint32_t> offsets_;
  cl::Buffer<float> pixels_;
  cl::Buffer<uint32_t> kept_runs_;  // one unused entry when nothing is ignored
};

}  // namespace lorgnette::nerf
