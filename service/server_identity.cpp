// Server homes as locked slot files in the data folder (server_identity.h).
#include "service/server_identity.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>

#include <filesystem>
#include <regex>
#include <stdexcept>

#include "service/tokens.h"

namespace fs = std::filesystem;

namespace lorgnette::service {
namespace {

// The slot's id: read when the file has one, else written (a new slot). Only the holder of the
// slot's lock reads or writes it.
std::string slot_id(int fd, const std::string& path) {
  char buf[64] = {};
  const ssize_t n = ::pread(fd, buf, sizeof(buf) - 1, 0);
  static const std::regex hex("[0-9a-f]{16}");
  std::string id(buf, n > 0 ? size_t(n) : 0);
  while (!id.empty() && (id.back() == '\n' || id.back() == ' ')) id.pop_back();
  if (std::regex_match(id, hex)) return id;
  id = random_hex(8);
  const std::string line = id + "\n";
  if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, line.data(), line.size(), 0) != ssize_t(line.size()) ||
      ::fsync(fd) != 0)
    throw std::runtime_error(fmt::format("cannot write the server's identity to '{}'", path));
  return id;
}

}  // namespace

std::string host_name() {
  char buf[256] = {};
  if (::gethostname(buf, sizeof(buf) - 1) != 0 || !buf[0]) return "localhost";
  std::string h = buf;
  // A file name part: anything but letters, digits, '.', '-' and '_' becomes '_'.
  for (char& c : h)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
  return h;
}

JobOwner ephemeral_owner() {
  const std::string host = host_name();
  return {random_hex(8) + "@" + host, random_hex(8) + "@" + host};
}

ServerIdentity::ServerIdentity(const std::string& data_dir) {
  const std::string host = host_name();
  const fs::path dir = fs::path(data_dir) / "servers";
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error(fmt::format("cannot make '{}': {}", dir.string(), ec.message()));
  for (int n = 0;; ++n) {
    const std::string path = (dir / fmt::format("{}.{}", host, n)).string();
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) throw std::runtime_error(fmt::format("cannot open the server slot '{}'", path));
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      ::close(fd);  // a live server holds it
      continue;
    }
    try {
      owner_ = {random_hex(8) + "@" + host, slot_id(fd, path) + "@" + host};
    } catch (...) {
      ::close(fd);
      throw;
    }
    fd_ = fd, slot_ = path;
    return;
  }
}

ServerIdentity::~ServerIdentity() {
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace lorgnette::service
