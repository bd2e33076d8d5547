// A one-node Slurm cluster of the test's own (Debian slurm-wlm and munge, no systemd): munged as
// the munge user with a fresh key (mode 0400) and its socket in a temporary folder, slurmctld and
// slurmd in the foreground (-D) from a small slurm.conf (proctrack/linuxproc, task/none,
// select/cons_tres, one node `localhost` with this machine's CPUs, free ports, state, spool, logs
// and pid files in the temporary folder, finished jobs in a jobcomp/filetxt file). SLURM_CONF is
// set in this process so the clients (sbatch, squeue, ...) and every child reach this cluster.
// The destructor cancels every job, waits for them, and stops the daemons, also when a test failed.
// Slurm's daemons and munge's key need root: unavailable() says why a machine cannot run it.
#pragma once
#include <netinet/in.h>
#include <pwd.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <optional>
#include <string>
#include <thread>

#include "service/child_process.h"
#include "service/command.h"
#include "service_test_util.h"

namespace lorgnette::service::test {

class SlurmCluster {
 public:
  // Why this machine cannot start the cluster ("" = it can).
  static std::string unavailable() {
    if (::geteuid() != 0) return "starting slurmctld/slurmd and munged needs root";
    for (const char* p : {"/usr/sbin/munged", "/usr/sbin/slurmctld", "/usr/sbin/slurmd", "/usr/bin/sbatch",
                          "/usr/bin/setpriv"})
      if (!fs::exists(p))
        return std::string(p) + " is missing: install slurm-wlm and munge (tools/setup-debian.sh)";
    if (!::getpwnam("munge")) return "there is no munge user: install munge";
    return "";
  }

  // Throws with the daemons' logs when the node does not become idle within 60 s.
  SlurmCluster() {
    char tmpl[] = "/tmp/lgn-slurm-XXXXXX";  // short: a Unix socket path has at most 107 bytes
    if (!::mkdtemp(tmpl)) throw std::runtime_error("mkdtemp failed");
    dir_ = tmpl;
    fs::permissions(dir_, fs::perms(0755));
    for (const char* d : {"munge", "state", "spool", "log"}) fs::create_directories(dir_ / d);
    start_munge();
    write_file(conf(), config());
    ::setenv("SLURM_CONF", conf().c_str(), 1);
    ctld_.emplace(std::vector<std::string>{"/usr/sbin/slurmctld", "-D", "-i"},
                  (dir_ / "log/ctld.out").string());
    slurmd_.emplace(std::vector<std::string>{"/usr/sbin/slurmd", "-D", "-N", "localhost"},
                    (dir_ / "log/slurmd.out").string());
    if (!wait_for([&] { return client({"sinfo", "--noheader", "--format=%T"}) == "idle\n"; }, 60.0)) {
      const std::string logs = read_file(dir_ / "log/slurmctld.log") + read_file(dir_ / "log/slurmd.log");
      stop();
      throw std::runtime_error("the Slurm node did not become idle:\n" + logs);
    }
  }
  ~SlurmCluster() { stop(); }
  SlurmCluster(const SlurmCluster&) = delete;
  SlurmCluster& operator=(const SlurmCluster&) = delete;

  fs::path dir() const { return dir_; }
  fs::path jobcomp() const { return dir_ / "log/jobcomp.txt"; }  // one line per finished job
  // A client program's stdout ("" when it failed).
  std::string client(const std::vector<std::string>& args) const {
    std::vector<std::string> argv{find_program(args.at(0))};
    argv.insert(argv.end(), args.begin() + 1, args.end());
    CommandResult r = run_command(argv, 30.0);
    return r.ok() ? r.out : "";
  }

 private:
  fs::path conf() const { return dir_ / "slurm.conf"; }

  static int free_port() {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
    ::close(fd);
    return ntohs(a.sin_port);
  }

  std::string config() const {
    const std::string d = dir_.string();
    return "ClusterName=lgntest\nSlurmctldHost=localhost\nSlurmUser=root\nSlurmdUser=root\n"
           "AuthType=auth/munge\nCredType=cred/munge\nAuthInfo=socket=" +
           d +
           "/munge/munge.sock\n"
           "ProctrackType=proctrack/linuxproc\nTaskPlugin=task/none\nSelectType=select/cons_tres\n"
           "SelectTypeParameters=CR_Core\nMpiDefault=none\nReturnToService=2\n"
           "SlurmctldPort=" +
           std::to_string(free_port()) + "\nSlurmdPort=" + std::to_string(free_port()) +
           "\nStateSaveLocation=" + d + "/state\nSlurmdSpoolDir=" + d +
           "/spool\n"
           "SlurmctldPidFile=" +
           d + "/slurmctld.pid\nSlurmdPidFile=" + d +
           "/slurmd.pid\n"
           "SlurmctldLogFile=" +
           d + "/log/slurmctld.log\nSlurmdLogFile=" + d +
           "/log/slurmd.log\n"
           "JobCompType=jobcomp/filetxt\nJobCompLoc=" +
           d +
           "/log/jobcomp.txt\nKillWait=5\n"
           "NodeName=localhost NodeAddr=127.0.0.1 CPUs=" +
           std::to_string(std::thread::hardware_concurrency()) +
           " State=UNKNOWN\nPartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP\n";
  }

  // munged refuses a key others can read and a socket folder others cannot enter.
  void start_munge() {
    const fs::path m = dir_ / "munge";
    const passwd* pw = ::getpwnam("munge");
    std::string key(1024, '\0');
    std::ifstream("/dev/urandom", std::ios::binary).read(key.data(), std::streamsize(key.size()));
    write_file(m / "munge.key", key);
    for (const fs::path& p : {m, m / "munge.key"})
      if (::chown(p.c_str(), pw->pw_uid, pw->pw_gid) != 0) throw std::runtime_error("chown " + p.string());
    fs::permissions(m / "munge.key", fs::perms::owner_read);
    munged_.emplace(
        std::vector<std::string>{
            "/usr/bin/setpriv", "--reuid=munge", "--regid=munge", "--init-groups", "/usr/sbin/munged", "-F",
            "--socket=" + (m / "munge.sock").string(), "--key-file=" + (m / "munge.key").string(),
            "--pid-file=" + (m / "munged.pid").string(), "--log-file=" + (m / "munged.log").string(),
            "--seed-file=" + (m / "munged.seed").string()},
        (dir_ / "log/munged.out").string());
    if (!wait_for([&] { return fs::exists(m / "munge.sock"); }, 20.0))
      throw std::runtime_error("munged did not start: " + read_file(dir_ / "log/munged.out"));
  }

  static void end(std::optional<ChildProcess>& p) {
    if (!p) return;
    p->signal(SIGTERM);
    if (!wait_for([&] { return p->poll().has_value(); }, 10.0)) p.reset();  // SIGKILL and reap
    p.reset();
  }

  // Jobs first (slurmstepd outlives slurmd), then the daemons, then the folder.
  void stop() {
    if (slurmd_ && ctld_) {
      client({"scancel", "--me"});
      wait_for([&] { return client({"squeue", "--noheader", "--me"}).empty(); }, 20.0);
    }
    end(slurmd_);
    end(ctld_);
    end(munged_);
    std::error_code ec;
    if (!::getenv("LGN_KEEP_SLURM_DIR")) fs::remove_all(dir_, ec);
  }

  fs::path dir_;
  std::optional<ChildProcess> munged_, ctld_, slurmd_;
};

}  // namespace lorgnette::service::test
