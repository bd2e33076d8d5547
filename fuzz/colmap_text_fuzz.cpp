// Fuzz target: COLMAP's text model readers (cameras.txt, images.txt, points3D.txt). Every input
// goes to all three, so one corpus serves them all.
#include <cstdint>
#include <exception>
#include <string>

#include "capture/colmap_model_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace lorgnette::capture;
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    parse_cameras_text(bytes, "cameras.txt");
  } catch (const std::exception&) {
  }
  try {
    parse_images_text(bytes, "images.txt");
  } catch (const std::exception&) {
  }
  try {
    parse_points3d_text(bytes, "points3D.txt");
  } catch (const std::exception&) {
  }
  return 0;
}
