// OpenImageIO-backed image reading and writing; see image_io.h.
#include "host/util/image_io.h"

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace lorgnette {
namespace fs = std::filesystem;
namespace {

std::string lower_ext(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

std::string temp_name(const std::string& path) {
  fs::path p(path);
  // Keep the extension last so OpenImageIO picks the right writer for the temporary file.
  return (p.parent_path() / fmt::format(".{}.{}.tmp{}", p.stem().string(), getpid(), p.extension().string()))
      .string();
}

}  // namespace

std::string decode_error_text(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  for (size_t i = text.find('\n'); i != std::string::npos; i = text.find('\n', i)) text.replace(i, 1, "; ");
  return text.empty() ? "the decoder gave no reason" : text;
}

float srgb_to_linear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

float linear_to_srgb(float c) {
  c = std::clamp(c, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

Image read_image(const std::string& path) {
  if (!fs::exists(path)) throw std::runtime_error(fmt::format("image '{}' does not exist", path));
  auto in = OIIO::ImageInput::open(path);
  if (!in)
    throw std::runtime_error(
        fmt::format("cannot read image '{}': {} (is it a valid PNG/JPEG/EXR?)", path, OIIO::geterror()));
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw std::runtime_error(fmt::format("image '{}' has no pixels", path));
  Image img(spec.width, spec.height, spec.nchannels);
  // A JPEG cut inside its scan data decodes "successfully" (the missing rows come back grey) with
  // only a recorded error, so the error state is checked as well as the return value.
  bool ok = in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, img.pixels.data());
  if (!ok || in->has_error())
    throw std::runtime_error(
        fmt::format("image '{}' is corrupt or truncated: {}", path, decode_error_text(in->geterror())));
  bool encoded =
      spec.format.basetype == OIIO::TypeDesc::UINT8 || spec.format.basetype == OIIO::TypeDesc::UINT16;
  if (encoded) {
    int colour = std::min(spec.nchannels, 3);
    if (spec.alpha_channel >= 0 && spec.alpha_channel < colour) colour = spec.alpha_channel;
    for (size_t i = 0; i < img.pixels.size(); ++i)
      if (static_cast<int>(i % spec.nchannels) < colour) img.pixels[i] = srgb_to_linear(img.pixels[i]);
  }
  in->close();
  return img;
}

void write_image(const std::string& path, const Image& image) {
  if (image.empty()) throw std::runtime_error(fmt::format("refusing to write empty image '{}'", path));
  std::string ext = lower_ext(path);
  bool is_float = ext == ".exr" || ext == ".hdr";
  int channels = image.channels;
  if (ext == ".jpg" || ext == ".jpeg") channels = std::min(channels, 3);
  OIIO::ImageSpec spec(image.width, image.height, channels,
                       is_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  std::vector<float> data(static_cast<size_t>(image.width) * image.height * channels);
  for (size_t p = 0; p < static_cast<size_t>(image.width) * image.height; ++p)
    for (int c = 0; c < channels; ++c) {
      float v = image.pixels[p * image.channels + c];
      bool colour = c < 3 && !(image.channels == 2 && c == 1) && !(image.channels == 4 && c == 3);
      data[p * channels + c] = is_float ? v : (colour ? linear_to_srgb(v) : std::clamp(v, 0.0f, 1.0f));
    }
  std::string tmp = temp_name(path);
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw std::runtime_error(fmt::format("no image writer for '{}' (use .png, .jpg or .exr)", path));
  if (!out->open(tmp, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, data.data()) || !out->close()) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw std::runtime_error(fmt::format("cannot write image '{}': {}", path, out->geterror()));
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error(fmt::format("cannot write image '{}': {}", path, ec.message()));
  }
}

void write_text_file_atomic(const std::string& path, const std::string& text) {
  std::string tmp = path + fmt::format(".{}.tmp", getpid());
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    out.flush();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw std::runtime_error(fmt::format("cannot write '{}' (disk full or directory not writable?)", path));
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error(fmt::format("cannot write '{}': {}", path, ec.message()));
  }
}

}  // namespace lorgnette
