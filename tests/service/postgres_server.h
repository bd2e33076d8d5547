// A real PostgreSQL server for one test: `initdb` and `pg_ctl` from Debian's postgresql package in a
// fresh folder under /tmp, listening only on a Unix socket in that folder (listen_addresses=''),
// stopped and removed by the destructor, so also when the test fails. PostgreSQL refuses to run as
// root, so as root the server runs as the `postgres` user (runuser) and the folder is theirs.
// Where the binaries are absent or the user cannot be switched the test skips with the reason
// (LGN_SKIP_UNLESS_POSTGRES). A folder left by a test process that was killed (its server too) is
// stopped and removed by the next start.
#pragma once
#include <gtest/gtest.h>
#include <pwd.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "service/child_process.h"

namespace lorgnette::service::test {

class ScopedPostgres {
 public:
  ScopedPostgres() {
    bin_ = find_bin_dir();
    if (bin_.empty()) {
      why_ = "no PostgreSQL server binaries (/usr/lib/postgresql/*/bin/initdb): install Debian's postgresql";
      return;
    }
    if (!prepare_user()) return;
    remove_stale();
    std::string tmpl = "/tmp/lgn-pg-" + std::to_string(::getpid()) + "-XXXXXX";
    if (!::mkdtemp(tmpl.data())) throw std::runtime_error("cannot make a folder for PostgreSQL under /tmp");
    dir_ = tmpl;
    if (::geteuid() == 0 && ::chown(dir_.c_str(), uid_, gid_) != 0)
      throw std::runtime_error("cannot give " + dir_.string() + " to the postgres user");
    if (run({(bin_ / "initdb").string(), "-D", (dir_ / "db").string(), "-A", "trust", "-U", "lorgnette", "-E",
             "UTF8", "--no-sync"}) != 0)
      throw std::runtime_error("initdb failed: " + log());
    const std::string opts = "-c listen_addresses='' -k " + dir_.string() + " -c fsync=off";
    if (run({(bin_ / "pg_ctl").string(), "-D", (dir_ / "db").string(), "-l", (dir_ / "server.log").string(),
             "-o", opts, "-w", "-t", "30", "start"}) != 0)
      throw std::runtime_error("pg_ctl start failed: " + log());
    running_ = true;
  }
  ~ScopedPostgres() {
    if (running_) stop_server(dir_);
    std::error_code ec;
    if (!dir_.empty()) std::filesystem::remove_all(dir_, ec);
  }
  ScopedPostgres(const ScopedPostgres&) = delete;
  ScopedPostgres& operator=(const ScopedPostgres&) = delete;

  bool running() const { return running_; }
  const std::string& why() const { return why_; }
  // libpq keywords for the server's socket, superuser `lorgnette`, database `postgres`.
  std::string conninfo() const { return "host=" + dir_.string() + " user=lorgnette dbname=postgres"; }
  // The same as a URI, as `serve --db` takes it.
  std::string uri() const { return "postgresql://lorgnette@/postgres?host=" + dir_.string(); }

 private:
  static std::filesystem::path find_bin_dir() {
    std::filesystem::path best;
    std::error_code ec;
    for (auto it = std::filesystem::directory_iterator("/usr/lib/postgresql", ec);
         !ec && it != std::filesystem::directory_iterator(); ++it)
      if (std::filesystem::exists(it->path() / "bin" / "initdb") && it->path() / "bin" > best)
        best = it->path() / "bin";
    return best;
  }
  bool prepare_user() {
    if (::geteuid() != 0) return true;  // not root: the server runs as this user
    const passwd* pw = ::getpwnam("postgres");
    for (const char* p : {"/usr/sbin/runuser", "/sbin/runuser"})
      if (std::filesystem::exists(p)) runuser_ = p;
    if (!pw || runuser_.empty()) {
      why_ = "running as root, and no postgres user or runuser to run PostgreSQL as (it refuses root)";
      return false;
    }
    uid_ = pw->pw_uid, gid_ = pw->pw_gid;
    if (run({"/bin/true"}) != 0) {
      why_ = "cannot switch to the postgres user with runuser (a container without that capability?)";
      return false;
    }
    return true;
  }
  int run(std::vector<std::string> argv) const {
    if (!runuser_.empty()) argv.insert(argv.begin(), {runuser_, "-u", "postgres", "--"});
    const std::string log_path = dir_.empty() ? "/dev/null" : (dir_ / "tool.log").string();
    ChildEnd e = ChildProcess(argv, log_path).wait();
    return e.exited ? e.code : 128 + e.signal;
  }
  std::string log() const {
    std::stringstream ss;
    for (const char* name : {"tool.log", "server.log"}) ss << std::ifstream(dir_ / name).rdbuf();
    return ss.str();
  }
  void stop_server(const std::filesystem::path& dir) const {
    run({(bin_ / "pg_ctl").string(), "-D", (dir / "db").string(), "-m", "immediate", "-w", "stop"});
  }
  // Folders of test processes that no longer exist: their servers outlived them.
  void remove_stale() const {
    std::error_code ec;
    for (auto it = std::filesystem::directory_iterator("/tmp", ec);
         !ec && it != std::filesystem::directory_iterator(); ++it) {
      const std::string name = it->path().filename();
      if (name.rfind("lgn-pg-", 0) != 0) continue;
      const pid_t pid = pid_t(std::atoi(name.c_str() + 7));
      if (pid <= 0 || ::kill(pid, 0) == 0 || errno != ESRCH) continue;
      stop_server(it->path());
      std::filesystem::remove_all(it->path(), ec);
    }
  }

  std::filesystem::path bin_, dir_;
  std::string runuser_, why_;
  uid_t uid_ = 0;
  gid_t gid_ = 0;
  bool running_ = false;
};

}  // namespace lorgnette::service::test

#define LGN_SKIP_UNLESS_POSTGRES(pg) \
  if (!(pg).running()) GTEST_SKIP() << (pg).why()
