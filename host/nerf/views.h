// Training/evaluation views on the device: the cameras, the pixel offset of each image inside one
// concatenated pixel array, and the pixels themselves (linear straight-alpha RGBA, 4 floats each).
// The sampler picks training pixels uniformly over all of them.
#pragma once
#include <cstdint>
#include <vector>

#include "common/camera_types.h"
#include "host/cl/buffer.h"
#include "host/util/image_io.h"

namespace lorgnette::nerf {

// One posed image; `image` may be null for render-only views (4 channels: linear RGBA).
struct View {
  Camera camera{};
  const Image* image = nullptr;
};

class DeviceViews {
 public:
  // with_pixels: upload the images (every view must have one of its camera's size).
  DeviceViews(cl::Runtime& rt, const std::vector<View>& views, bool with_pixels);

  uint32_t count() const { return count_; }
  uint64_t total_pixels() const { return total_pixels_; }
  const std::vector<Camera>& cameras() const { return host_cameras_; }
  const cl::Buffer<Camera>& camera_buffer() const { return cameras_; }
  const cl::Buffer<uint32_t>& offsets() const { return offsets_; }
  const cl::Buffer<float>& pixels() const { return pixels_; }

 private:
  uint32_t count_ = 0;
  uint64_t total_pixels_ = 0;
  std::vector<Camera> host_cameras_;
  cl::Buffer<Camera> cameras_;
  cl::Buffer<uint32_t> offsets_;
  cl::Buffer<float> pixels_;
};

}  // namespace lorgnette::nerf
