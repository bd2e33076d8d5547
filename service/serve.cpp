// The server's main loop (serve.h).
#include "service/serve.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "host/util/image_io.h"
#include "host/util/interrupt.h"
#include "service/lease_keeper.h"
#include "service/server_identity.h"
#include "service/store_selection.h"

namespace fs = std::filesystem;

namespace lorgnette::service {
namespace {

void drain_workers(Executor& executor, double grace_seconds) {
  executor.interrupt_all();
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(grace_seconds);
  while (executor.running() > 0 && std::chrono::steady_clock::now() < end) {
    executor.tick();
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  if (executor.running() > 0)
    spdlog::warn("{} worker(s) did not stop within {} s; their jobs are handed back at the next start",
                 executor.running(), grace_seconds);
}

std::unique_ptr<Executor> make_executor(const ServeOptions& o, JobStore& store, const LeaseSettings& lease) {
  if (o.executor == "local") {
    LocalExecutorOptions l = o.local;
    l.lease = lease;
    return std::make_unique<LocalExecutor>(store, l);
  }
  if (o.executor == "slurm") {
    SlurmExecutorOptions s = o.slurm;
    s.data_dir = fs::absolute(o.data_dir).string();  // the nodes start in the job folder, not here
    s.max_attempts = o.local.max_attempts;
    s.worker_exe = o.local.worker_exe;
    s.global_flags = o.local.global_flags;
    s.lease = lease;
    return std::make_unique<SlurmExecutor>(store, s);
  }
  throw std::runtime_error("--executor '" + o.executor + "' is not one of: local, slurm");
}

}  // namespace

void run_serve(ServeOptions o) {
  if (o.data_dir.empty())
    throw std::runtime_error("serve needs --data DIR (uploads, models, fits and the job store)");
  o.api.job.validate();  // before anything is created
  fs::create_directories(o.data_dir);
  if (o.db.empty()) o.db = (fs::path(o.data_dir) / "jobs.sqlite").string();
  o.local.data_dir = o.api.data_dir = o.data_dir;
  auto store = open_job_store(o.db);
  const ServerIdentity identity(o.data_dir);  // held for the process's life
  if (!(o.lease_seconds >= 1.0)) throw std::runtime_error("--lease-seconds must be at least 1");
  const LeaseSettings lease{identity.owner(), o.lease_seconds};
  const std::unique_ptr<Executor> owned = make_executor(o, *store, lease);
  Executor& executor = *owned;
  executor.reconcile();
  const LeaseKeeper keeper(*store, lease);
  spdlog::info("server {} (home {}, slot '{}'); running jobs' leases last {} s", lease.owner.instance,
               lease.owner.home, identity.slot_path(), lease.lease_seconds);
  Api api(o.api, *store, executor);
  HttpServer http(api, o.http);
  http.start();
  if (!o.port_file.empty()) write_text_file_atomic(o.port_file, std::to_string(http.port()) + "\n");
  spdlog::info("serving the try-on API on http://{}:{}/api/v1 (data '{}', store {}, executor {})",
               o.http.host, http.port(), o.data_dir, describe_job_store(o.db),
               o.executor == "local" ? std::to_string(o.local.slots) + " local worker slot(s)" : o.executor);
  auto last_sweep = std::chrono::steady_clock::time_point{};
  while (!interrupted()) {
    executor.tick();
    if (std::chrono::steady_clock::now() - last_sweep > std::chrono::seconds(60)) {
      api.sweep_retention(unix_now());
      last_sweep = std::chrono::steady_clock::now();
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  spdlog::info("stopping: no new requests; running stages are asked to stop and go back to the queue");
  http.stop();
  drain_workers(executor, o.grace_seconds);
  clear_interrupt();  // a stop on SIGINT/SIGTERM is the server's normal end: exit status 0
}

}  // namespace lorgnette::service
