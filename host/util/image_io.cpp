// OpenImageIO-backed image reading and writing; see image_io.h.
#include "host/util/image_io.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "host/util/file_write.h"

namespace lorgnette {
namespace fs = std::filesystem;
namespace {

std::string lower_ext(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

// Encodes the image in memory and writes the bytes through write_file_atomic, whose every write
// is checked: OpenImageIO's PNG writer does not report a full disk when it writes a file itself.
// A format without in-memory output is written to the temporary file by OpenImageIO and read back
// whole before the rename, so a short file is never published either.
void write_encoded(const std::string& path, const OIIO::ImageSpec& spec, OIIO::TypeDesc type,
                   const void* data) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw std::runtime_error(fmt::format("no image writer for '{}' (use .png, .jpg or .exr)", path));
  if (out->supports("ioproxy")) {
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput proxy(bytes);
    out->set_ioproxy(&proxy);
    if (!out->open(path, spec) || !out->write_image(type, data) || !out->close())
      throw std::runtime_error(fmt::format("cannot encode image '{}': {}", path, out->geterror()));
    write_file_atomic(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
    return;
  }
  const std::string tmp = temporary_path_for(path);
  std::error_code ec;
  bool ok = out->open(tmp, spec) && out->write_image(type, data) && out->close();
  std::string why = ok ? "" : out->geterror();
  if (ok) try {
      read_image(tmp);
    } catch (const std::exception& e) {
      ok = false, why = e.what();
    }
  if (ok) fs::rename(tmp, path, ec);
  if (!ok || ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error(
        fmt::format("cannot write image '{}': {} (is the disk full?)", path, ok ? ec.message() : why));
  }
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
  write_encoded(path, spec, OIIO::TypeDesc::FLOAT, data.data());
}

void write_srgb8_image(const std::string& path, int width, int height, int channels, const uint8_t* pixels) {
  if (width <= 0 || height <= 0 || channels <= 0)
    throw std::runtime_error(fmt::format("refusing to write empty image '{}'", path));
  OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::UINT8);
  write_encoded(path, spec, OIIO::TypeDesc::UINT8, pixels);
}

void write_text_file_atomic(const std::string& path, const std::string& text) {
  write_file_atomic(path, text);
}

}  // namespace lorgnette
