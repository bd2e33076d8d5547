// Fuzz target: COLMAP's binary model readers (cameras.bin, images.bin, points3D.bin). Every input
// goes to all three, so one corpus serves them all.
#include <cstdint>
#include <exception>
#include <string>

#include "capture/colmap_model_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace lorgnette::capture;
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    parse_cameras_binary(bytes, "cameras.bin");
  } catch (const std::exception&) {
  }
  try {
    parse_images_binary(bytes, "images.bin");
  } catch (const std::exception&) {
  }
  try {
    parse_points3d_binary(bytes, "points3D.bin");
  } catch (const std::exception&) {
  }
  return 0;
}
