// Magic numbers of the accepted uploads (content_type.h).
#include "service/content_type.h"

#include <fstream>

namespace lorgnette::service {

Sniffed sniff_bytes(std::string_view h) {
  auto at = [&](size_t offset, std::string_view magic) { return h.substr(offset, magic.size()) == magic; };
  if (h.size() >= 12 && at(4, "ftyp")) {
    // ISO base media: QuickTime brands ("qt  ") are .mov, the rest (isom, mp42, 3gp...) .mp4.
    return {UploadKind::Video, at(8, "qt  ") ? ".mov" : ".mp4"};
  }
  if (at(0, "\x1A\x45\xDF\xA3"))
    return {UploadKind::Video, h.find("webm") != std::string_view::npos ? ".webm" : ".mkv"};
  if (h.size() >= 12 && at(0, "RIFF") && at(8, "AVI ")) return {UploadKind::Video, ".avi"};
  if (at(0, "\xFF\xD8\xFF")) return {UploadKind::Image, ".jpg"};
  if (at(0, "\x89PNG\r\n\x1A\n")) return {UploadKind::Image, ".png"};
  return {};
}

Sniffed sniff_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  char buf[64] = {};
  in.read(buf, sizeof buf);
  return sniff_bytes(std::string_view(buf, size_t(in.gcount())));
}

}  // namespace lorgnette::service
