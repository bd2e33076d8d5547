// Fuzz target: transforms.json through the dataset loader (host/dataset/dataset.h, with cameras
// only: image headers are read, pixels are not). The input becomes transforms.json in a private
// directory that also holds three 8x6 images, img_0.png .. img_2.png, and their masks mask_0.png ..
// mask_2.png (plus a 4x3 mask_small.png), so frames can resolve their files and mask_path, and the
// intrinsics and masks are checked against real image sizes.
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include "host/dataset/dataset.h"
#include "host/util/image_io.h"

namespace {
namespace fs = std::filesystem;

// The private directory, made on first use and removed at exit.
struct Scratch {
  fs::path dir = fs::temp_directory_path() / fmt::format("lgn-fuzz-transforms-{}", getpid());
  Scratch() {
    spdlog::set_level(spdlog::level::off);  // the loader's warnings would flood the fuzzer's output
    fs::create_directories(dir);
    for (int i = 0; i < 3; ++i) {
      lorgnette::write_image((dir / fmt::format("img_{}.png", i)).string(), lorgnette::Image(8, 6, 3, 0.5f));
      lorgnette::write_image((dir / fmt::format("mask_{}.png", i)).string(), lorgnette::Image(8, 6, 1, 1.0f));
    }
    // One mask of another size than the images, for mask_path's size check.
    lorgnette::write_image((dir / "mask_small.png").string(), lorgnette::Image(4, 3, 1, 1.0f));
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

const fs::path& dataset_dir() {
  static const Scratch scratch;
  return scratch.dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const fs::path& dir = dataset_dir();
  {
    std::ofstream f(dir / "transforms.json", std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  lorgnette::dataset::LoadOptions options;
  options.load_images = false;
  options.any_missing_images_ok = true;
  try {
    lorgnette::dataset::Dataset ds = lorgnette::dataset::load_dataset(dir.string(), options);
    ds.camera_bounds();
  } catch (const std::exception&) {
  }
  return 0;
}
