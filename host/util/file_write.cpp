// Checked, atomic file writes; see file_write.h.
#include "host/util/file_write.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace lorgnette {
namespace fs = std::filesystem;
namespace {

std::string advice(int err) {
  if (err == ENOSPC || err == EDQUOT) return "the disk is full: free some space or choose another output";
  if (err == EACCES || err == EPERM || err == EROFS)
    return "the folder is not writable: check its permissions or choose another output";
  return "check the path and the disk";
}

[[noreturn]] void fail(const std::string& path, const char* step, int err) {
  throw std::runtime_error(
      fmt::format("cannot write '{}': {} failed: {} ({})", path, step, std::strerror(err), advice(err)));
}

// The whole of `bytes` into `fd`, retrying short writes and EINTR; returns the errno of a failure.
int write_all(int fd, std::string_view bytes) {
  const char* p = bytes.data();
  size_t left = bytes.size();
  while (left > 0) {
    ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return n < 0 ? errno : ENOSPC;
    p += n;
    left -= size_t(n);
  }
  return 0;
}

// Flushes the folder holding `path` to disk so a rename into it survives a power cut. A folder that
// cannot be opened or synced (some network filesystems refuse fsync on folders) costs durability,
// not correctness: the file itself is already whole and renamed, so this is best effort.
void sync_parent_folder(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  int dir = ::open(parent.empty() ? "." : parent.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir < 0) return;
  while (::fsync(dir) != 0 && errno == EINTR) {
  }
  ::close(dir);
}

}  // namespace

std::string temporary_path_for(const std::string& path) {
  fs::path p(path);
  return (p.parent_path() / fmt::format(".{}.{}.tmp{}", p.stem().string(), getpid(), p.extension().string()))
      .string();
}

void write_file_atomic(const std::string& path, std::string_view bytes) {
  const std::string tmp = temporary_path_for(path);
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail(path, "creating a temporary file", errno);
  // fsync before the rename: without it a power cut after the rename can leave the new name on an
  // empty or partial file (the rename reaches the disk before the data). fsync and close are
  // checked too: on network filesystems and with delayed allocation a full disk may show only there.
  int err = write_all(fd, bytes);
  if (err == 0 && ::fsync(fd) != 0 && errno != EINVAL) err = errno;  // EINVAL: a file that cannot sync
  if (::close(fd) != 0 && err == 0) err = errno;
  std::error_code ec;
  if (err != 0) {
    fs::remove(tmp, ec);
    fail(path, "writing", err);
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    fail(path, "renaming the finished file into place", ec.value());
  }
  sync_parent_folder(path);  // the rename itself reaches the disk
}

void check_writable_folder(const std::string& dir, const std::string& what) {
  const std::string folder = dir.empty() ? "." : dir;
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw std::runtime_error(fmt::format(
        "cannot write {}: the folder '{}' does not exist; create it or choose another path", what, folder));
  const std::string probe = (fs::path(folder) / fmt::format(".lorgnette-write-probe-{}", getpid())).string();
  try {
    write_file_atomic(probe, std::string(4096, '\0'));
  } catch (const std::exception& e) {
    throw std::runtime_error(
        fmt::format("cannot write {} into '{}' (checked before starting): {}", what, folder, e.what()));
  }
  fs::remove(probe, ec);
}

void check_written_file(const std::string& path, long long min_bytes) {
  std::error_code ec;
  auto size = fs::file_size(path, ec);
  if (ec || static_cast<long long>(size) < min_bytes)
    throw std::runtime_error(
        fmt::format("cannot write '{}': the file came out {} (is the disk full?)", path,
                    ec ? "missing" : fmt::format("{} bytes long, at least {} expected", size, min_bytes)));
}

}  // namespace lorgnette
