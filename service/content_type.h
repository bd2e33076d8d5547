// What an uploaded file is, judged by its first bytes and never by its name or the client's
// Content-Type: the video containers phones record (MP4/MOV, WebM/Matroska, AVI) and the photo
// formats (JPEG, PNG). Anything else is refused before a worker ever decodes it.
#pragma once
#include <filesystem>
#include <string>
#include <string_view>

namespace lorgnette::service {

enum class UploadKind { Unknown, Video, Image };

struct Sniffed {
  UploadKind kind = UploadKind::Unknown;
  std::string extension;  // ".mp4", ".mov", ".webm", ".mkv", ".avi", ".jpg", ".png"; "" when unknown
};

Sniffed sniff_bytes(std::string_view head);  // the file's first bytes (16 are enough)
Sniffed sniff_file(const std::filesystem::path& path);

}  // namespace lorgnette::service
