// Refuses paths that name something other than a regular file before a reader opens them. Opening a
// FIFO for reading blocks until a writer appears (forever, for a path a model or a placement merely
// names), and a device or a socket is never a file the user meant; both must be refused up front,
// not hang. And reads a whole file with those checks, the one reader of the file formats' bytes.
// Header-only, so the file parsers' fuzzers link nothing more.
#pragma once
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

namespace lorgnette {

// True when `path` exists and is a regular file (after following symlinks).
inline bool is_regular_file_path(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

// Throws std::runtime_error naming `what` and `path` when `path` exists but is not a regular file
// (a FIFO, a socket, a device or a directory). A missing path is left to the reader's own message.
inline void require_regular_file(const std::string& path, const std::string& what) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::file_status st = fs::status(path, ec);
  if (ec || st.type() == fs::file_type::not_found || st.type() == fs::file_type::regular) return;
  const char* kind = st.type() == fs::file_type::directory ? "a directory"
                     : st.type() == fs::file_type::fifo    ? "a FIFO (named pipe)"
                     : st.type() == fs::file_type::socket  ? "a socket"
                                                           : "a device or special file";
  throw std::runtime_error(
      fmt::format("{} '{}' is {}, not a regular file: give the path of a file", what, path, kind));
}

// The bytes of the file `path` (`what` names it in messages: "model file", "sidecar"). Throws
// std::runtime_error naming both when the path is no regular file (require_regular_file), cannot be
// opened (missing, no permission), or fails while being read, so an unreadable file never reaches a
// parser as an empty or cut text.
inline std::string read_regular_file(const std::string& path, const std::string& what) {
  require_regular_file(path, what);
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw std::runtime_error(
        fmt::format("cannot open {} '{}': check the path and its permissions", what, path));
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad())
    throw std::runtime_error(fmt::format("could not read {} '{}': the read failed part way", what, path));
  return bytes;
}

}  // namespace lorgnette
