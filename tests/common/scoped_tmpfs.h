// A small tmpfs mounted for one test, to try outputs on a full disk or a read-only folder the way a
// user meets them. Mounting needs root (the CI runs the tests as root); where it fails the test
// skips with the reason (use LGN_SKIP_UNLESS_MOUNTED).
#pragma once
#include <sys/mount.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace lgn_test {

class ScopedTmpfs {
 public:
  // Mounts a tmpfs of `bytes` at `dir` (created); read-only when `read_only`.
  // A mount left by a killed run (timeout, SIGKILL) is taken down first, and the folder emptied.
  ScopedTmpfs(const std::filesystem::path& dir, size_t bytes, bool read_only = false) : dir_(dir) {
    while (::umount2(dir.c_str(), MNT_DETACH) == 0) {
    }
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
    std::filesystem::create_directories(dir, ec);
    const std::string data = "size=" + std::to_string(bytes);
    unsigned long flags = read_only ? MS_RDONLY : 0;
    if (::mount("tmpfs", dir.c_str(), "tmpfs", flags, data.c_str()) == 0)
      mounted_ = true;
    else
      why_ = std::string("cannot mount a tmpfs at ") + dir.string() + ": " + std::strerror(errno) +
             " (these full-disk checks need root, e.g. the CI container)";
  }
  ~ScopedTmpfs() {
    if (!mounted_) return;
    ::umount2(dir_.c_str(), MNT_DETACH);
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  ScopedTmpfs(const ScopedTmpfs&) = delete;
  ScopedTmpfs& operator=(const ScopedTmpfs&) = delete;

  bool mounted() const { return mounted_; }
  const std::string& why() const { return why_; }
  const std::filesystem::path& path() const { return dir_; }

  // Fills the filesystem: afterwards no file can grow by a single block.
  void fill() const {
    std::ofstream f(dir_ / "filler", std::ios::binary);
    std::vector<char> block(4096, 'x');
    while (f.write(block.data(), block.size())) f.flush();
  }

 private:
  std::filesystem::path dir_;
  bool mounted_ = false;
  std::string why_;
};

}  // namespace lgn_test

#define LGN_SKIP_UNLESS_MOUNTED(tmpfs) \
  if (!(tmpfs).mounted()) GTEST_SKIP() << (tmpfs).why()
